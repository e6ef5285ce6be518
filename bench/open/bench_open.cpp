// The cost of open boundaries (issue 32 point 5, docs/open_boundaries.md): a 2D channel H = 1 m, L = 2 m with
// a uniform inlet and an outlet (Wendland C2, dummy walls, laminar viscosity, Verlet), the fluid moving at the
// inflow speed from the start, so that particles are created and removed from the first steps. Prints the particle count, the particles created and removed,
// the wall time of the steps and the share spent in the open-boundary work: the transitions with creation,
// removal and the sort after them, and the buffer update (kinematics, extrapolation at the ghost nodes).
// Timings only here, never in tests.
//   bench_open [--spacing DX] [--steps N] [--speed U] [--threads 1,2]
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "sim/open_boundaries.hpp"
#include "sim/simulation.hpp"

using namespace varsph;

int main(int argc, char** argv) {
  double dx = 0.01, speed = 2.0;
  int steps = 200;
  std::vector<int> threads = {1, 2};
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--spacing" && k + 1 < argc) dx = std::atof(argv[++k]);
    else if (a == "--steps" && k + 1 < argc) steps = std::atoi(argv[++k]);
    else if (a == "--speed" && k + 1 < argc) speed = std::atof(argv[++k]);
    else if (a == "--threads" && k + 1 < argc) {
      threads.clear();
      for (char* t = std::strtok(argv[++k], ","); t; t = std::strtok(nullptr, ",")) threads.push_back(std::atoi(t));
    } else {
      std::fprintf(stderr, "usage: bench_open [--spacing DX] [--steps N] [--speed U] [--threads 1,2]\n");
      return 2;
    }
  }
  const int layers = 3;  // Wendland support 2 h = 2.6 dx
  const double depth = layers * dx;
  nlohmann::json j = nlohmann::json::parse(R"({
    "name": "bench_open", "setup": "paper", "dimension": 2,
    "domain": {"min": [-0.5, -0.5], "max": [2.5, 1.5]},
    "kernel": {"type": "wendland_c2", "h_over_dx": 1.3},
    "fluid": {"rho0": 1000.0, "c0": 40.0},
    "physics": {"density": "continuity", "laminar_viscosity": {"nu": 0.001}},
    "boundary": {"model": "dummy_adami", "slip": "free_slip"},
    "integrator": {"type": "verlet", "cfl": 0.2}, "time": {"end": 100}})");
  j["particles"] = {{"spacing", dx}, {"max_count", 1e8}};
  j["bodies"] = nlohmann::json::array(
      {{{"kind", "fluid"}, {"shape", "box"}, {"min", {0.0, 0.0}}, {"max", {2.0, 1.0}}, {"velocity", {speed, 0.0}}},
       {{"kind", "boundary"}, {"shape", "tank"}, {"min", {-depth, 0.0}}, {"max", {2.0 + depth, 1.0}}, {"layers", 3},
        {"open", {true, true, false, false}}}});
  j["open_boundaries"] = nlohmann::json::array(
      {{{"name", "in"}, {"kind", "inlet"}, {"min", {-depth, 0.0}}, {"max", {0.0, 1.0}}, {"direction", {1.0, 0.0}},
        {"velocity", {{"profile", "uniform"}, {"value", speed}}}},
       {{"name", "out"}, {"kind", "outlet"}, {"min", {2.0, 0.0}}, {"max", {2.0 + depth, 1.0}}, {"direction", {-1.0, 0.0}}}});
  for (int t : threads) {
    omp_set_num_threads(t);
    Simulation<2> sim(scene::parse_scene_json(j, "bench_open.json"));
    for (int s = 0; s < 5; ++s) sim.advance();  // warm-up
    const auto* ob = sim.open_boundaries();
    const double tr0 = ob->transition_seconds(), im0 = ob->impose_seconds();
    const long c0 = sim.flow().created, r0 = sim.flow().removed_outlet;
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < steps; ++s) sim.advance();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double tr = ob->transition_seconds() - tr0, im = ob->impose_seconds() - im0;
    std::printf("threads %d: %zu particles (%zu buffer), %d steps in %.3f s (%.2f ms/step); created %ld, removed %ld; "
                "open-boundary work %.2f %% of a step (transitions, creation, removal and sort %.2f %%, buffer update "
                "%.2f %%)\n",
                t, sim.size(), ob->buffer_count(), steps, wall, 1e3 * wall / steps, sim.flow().created - c0,
                sim.flow().removed_outlet - r0, 100 * (tr + im) / wall, 100 * tr / wall, 100 * im / wall);
  }
  return 0;
}
