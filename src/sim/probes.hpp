#pragma once
// Probes defined in the scene's `probes` list (docs/results.md), sampled into probes.csv:
//   {"type": "pressure", "name": "gauge1", "point": [x, y(, z)],            -> p_gauge1 [Pa]
//    "radius": r, "normal": [..]}  (optional: a transducer face; see Probes::pressure_at)
//   {"type": "water_height", "name": "H1", "from": [x, y0(, z)], "to": y1}  -> h_H1 [m] above y0
//   {"type": "front", "name": "..." (optional)}                               -> front_x (largest fluid x) [m]
//   {"type": "force", "name": "obstacle", "body": 2, "moment_about": [..]}    -> Fx_obstacle, Fy_obstacle,
//        (Fz_), Mz_obstacle (2D) or Mx_, My_, Mz_ (3D) [N, N m; per metre of depth in 2D]
// Validation errors name `probes.N.key` (InputError, exit 2).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/scene.hpp"
#include "sim/simulation.hpp"

namespace varsph {

struct ProbeSpec {
  std::string type, name;
  std::vector<double> point;         // pressure: the centre of the face; water_height: the lower end of the line
  double radius = 0;                 // pressure: radius of the sensor face [m] (0: a point)
  std::vector<double> normal;        // pressure: face normal into the fluid (empty: from the nearest wall)
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
  // One value per column: geometric probes (front, water height) at the current state; load probes
  // (pressure, force) as the time mean over the steps accumulated since the previous sample (a
  // transducer integrates over its sampling interval), or at the current state when nothing was
  // accumulated (the first row, probes every step). Resets the accumulation.
  std::vector<double> sample(const Simulation<D>& sim);
  // Adds the load probes' current values, weighted by the step just taken (call after every step).
  void accumulate(const Simulation<D>& sim);
  // The accumulation in progress, for checkpoints (a restarted run samples the same means).
  nlohmann::json save_state() const;
  void restore_state(const nlohmann::json& j);

 private:
  std::vector<double> loads(const Simulation<D>& sim);  // pressure and force columns now
  double pressure_at(const Simulation<D>& sim, const ProbeSpec& p, std::size_t k) const;
  double fluid_pressure(const Simulation<D>& sim, const Vec<D>& x, const Vec<D>& n) const;
  double water_height(const Simulation<D>& sim, const ProbeSpec& p) const;
  void resolve_normals(const Simulation<D>& sim);
  std::vector<ProbeSpec> specs_;
  std::vector<Vec<D>> normals_;   // per probe: face normal into the fluid (zero: a point sensor)
  bool normals_resolved_ = false;
  std::vector<Vec<D>> force_;     // scratch: force on each boundary particle
  std::vector<double> sum_;       // load columns: sum of value x dt since the last sample
  double window_ = 0;             // time accumulated since the last sample [s]
};

}  // namespace varsph
