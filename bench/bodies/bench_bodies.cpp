// The cost of rigid bodies (docs/bodies.md, issue 30 point 7): a floating box in a 3D tank with the
// recommended engineering set-up; prints the fluid and body particle counts, ns per fluid particle-step and
// the share of a step spent in the coupling (reaction pass over the body's particles, contact pass, the
// ordered reduction, Newton-Euler; RigidBodies::seconds()), per thread count. Timings only here.
//   bench_bodies [--spacing DX] [--steps N] [--threads 1,2]
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bodies/rigid_bodies.hpp"
#include "scene/scene.hpp"
#include "sim/simulation.hpp"

using namespace varsph;

int main(int argc, char** argv) {
  double dx = 0.01;
  int steps = 10;
  std::vector<int> threads = {1, 2};
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--spacing" && k + 1 < argc) dx = std::atof(argv[++k]);
    else if (a == "--steps" && k + 1 < argc) steps = std::atoi(argv[++k]);
    else if (a == "--threads" && k + 1 < argc) {
      threads.clear();
      for (char* t = std::strtok(argv[++k], ","); t; t = std::strtok(nullptr, ",")) threads.push_back(std::atoi(t));
    } else {
      std::fprintf(stderr, "usage: bench_bodies [--spacing DX] [--steps N] [--threads 1,2]\n");
      return 2;
    }
  }
  nlohmann::json j = nlohmann::json::parse(R"({
    "name": "bench_bodies", "dimension": 3,
    "domain": {"min": [-0.1, -0.1, -0.1], "max": [1.1, 1.1, 0.7]},
    "kernel": {"type": "wendland_c2", "h_over_dx": 1.414}, "gravity": [0, 0, -9.81],
    "fluid": {"rho0": 1000.0, "c0": "auto", "c0_factor": 10},
    "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0, 0], "max": [1.0, 1.0, 0.4], "initial_pressure": "hydrostatic"},
               {"kind": "boundary", "shape": "tank", "min": [0, 0, 0], "max": [1.0, 1.0, 0.6], "layers": 3},
               {"kind": "rigid", "shape": "box", "min": [0.35, 0.35, 0.32], "max": [0.65, 0.65, 0.47], "density": 500}],
    "physics": {"density": "continuity", "riemann": {}}, "boundary": {"model": "dummy_adami"},
    "integrator": {"type": "symplectic_euler", "cfl": 0.2}, "time": {"end": 10}})");
  j["particles"] = {{"spacing", dx}, {"max_count", 1e8}};
  for (int t : threads) {
    omp_set_num_threads(t);
    Simulation<3> sim(scene::parse_scene_json(j, "bench_bodies.json"));
    std::size_t body = sim.rigid_bodies()->bodies()[0].count;
    sim.advance();  // warm-up: first-touch, tables
    const double s0 = sim.rigid_bodies()->seconds();
    const auto t0 = std::chrono::steady_clock::now();
    for (int n = 0; n < steps; ++n) sim.advance();
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double coupling = sim.rigid_bodies()->seconds() - s0;
    std::printf("threads %d: %zu fluid + %zu boundary particles (body %zu): %.1f ns per fluid particle-step, "
                "%.3f s per step, coupling %.4f s per step = %.2f %% of a step\n",
                t, sim.count(0), sim.count(1), body, 1e9 * total / (double(steps) * double(sim.count(0))),
                total / steps, coupling / steps, 100 * coupling / total);
  }
  return 0;
}
