#pragma once
// Probes defined in the scene's `probes` list (docs/results.md), sampled into probes.csv:
//   {"type": "pressure", "name": "gauge1", "point": [x, y(, z)]}            -> p_gauge1 [Pa]
//   {"type": "water_height", "name": "H1", "from": [x, y0(, z)], "to": y1}  -> h_H1 [m] above y0
//   {"type": "front", "name": "..." (optional)}                               -> front_x (largest fluid x) [m]
//   {"type": "force", "name": "obstacle", "body": 2, "moment_about": [..]}    -> Fx_obstacle, Fy_obstacle,
//        (Fz_), Mz_obstacle (2D) or Mx_, My_, Mz_ (3D) [N, N m; per metre of depth in 2D]
// Validation errors name `probes.N.key` (InputError, exit 2).
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "sim/simulation.hpp"

namespace varsph {

struct ProbeSpec {
  std::string type, name;
  std::vector<double> point;         // pressure: the point; water_height: the lower end of the line
  double top = 0;                    // water_height: upper end of the line (vertical coordinate)
  int body = -1;                     // force: index into the scene's bodies (a boundary body)
  std::vector<double> moment_about;  // force: reference point of the moment
};

// Parses and validates the scene's probes (no simulation needed; `varsph info` and tests use it).
std::vector<ProbeSpec> parse_probes(const scene::Scene& s);

template <int D>
class Probes {
 public:
  explicit Probes(const scene::Scene& s);
  bool empty() const { return specs_.empty(); }
  // Column names after `time`, in order.
  std::vector<std::string> columns() const;
  // One value per column for the simulation's current state.
  std::vector<double> sample(const Simulation<D>& sim);

 private:
  double pressure_at(const Simulation<D>& sim, const Vec<D>& x) const;
  double water_height(const Simulation<D>& sim, const ProbeSpec& p) const;
  std::vector<ProbeSpec> specs_;
  std::vector<Vec<D>> force_;  // scratch: force on each boundary particle
};

}  // namespace varsph
