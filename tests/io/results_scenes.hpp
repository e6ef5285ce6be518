#pragma once
// Tiny scenes for the results tests: a 2D dam break in a tank with an obstacle (about 300 particles).
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

namespace varsph::test {

// 2D dam break: water column 0.1 x 0.2 m in a 0.4 x 0.3 m tank, obstacle box on the floor (body 2),
// fixed dt = 2e-4 s (200 steps = 0.04 s), frames every 20 steps.
inline nlohmann::json tiny_dam_break(const std::string& integrator = "verlet") {
  return nlohmann::json::parse(R"({
    "name": "tiny",
    "setup": "paper", "dimension": 2,
    "domain": {"min": [-0.1, -0.1], "max": [0.5, 0.4]},
    "particles": {"spacing": 0.02},
    "kernel": {"type": "gaussian", "h_over_dx": 1.2},
    "fluid": {"rho0": 1000.0, "c0": 20.0},
    "gravity": [0.0, -9.81],
    "bodies": [
      {"kind": "fluid", "shape": "box", "min": [0.0, 0.0], "max": [0.1, 0.2], "initial_pressure": "hydrostatic"},
      {"kind": "boundary", "shape": "tank", "min": [0.0, 0.0], "max": [0.4, 0.3], "layers": 4},
      {"kind": "boundary", "shape": "box", "min": [0.3, 0.0], "max": [0.34, 0.04]}
    ],
    "physics": {"density": "continuity", "artificial_viscosity": {"alpha": 0.1, "beta": 0.0}},
    "boundary": {"model": "dynamic"},
    "integrator": {"type": "verlet", "dt": 0.0002},
    "time": {"end": 0.04},
    "output": {"every": 0.004, "precision": "float64"},
    "probes": [
      {"type": "pressure", "name": "g1", "point": [0.0, 0.02]},
      {"type": "water_height", "name": "H1", "from": [0.05, 0.0]},
      {"type": "front"},
      {"type": "force", "name": "obstacle", "body": 2, "moment_about": [0.32, 0.0]}
    ]
  })")
      .patch(nlohmann::json::parse(R"([{"op": "replace", "path": "/integrator/type", "value": ")" + integrator +
                                   R"("}])"));
}

inline std::filesystem::path write_scene(const std::filesystem::path& dir, const nlohmann::json& j,
                                         const std::string& file = "scene.json") {
  const auto p = dir / file;
  std::ofstream(p) << j.dump(2);
  return p;
}

}  // namespace varsph::test
