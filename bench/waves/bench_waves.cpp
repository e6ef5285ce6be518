// The cost of the wavemaker and the damping zone (issue 31 point 6, docs/waves.md "Cost"): the flumes of
// pipelines/waves/ (piston and flap, H/dx = 10, 34 k particles, the engineering set-up, a damping zone one
// wavelength long). Per scene and thread count prints the time of a step (the fastest of R rounds of N steps)
// and ns per particle-step, then
//   - the paddle motion: Simulation::move_boundaries timed alone at the run's time (one pass over every
//     particle, the signal evaluated once), times the 2 calls a step makes (at t_k before the forces, at
//     t_k + dt in the sort; explicit one-sort integrators);
//   - the damping zone: the pass of Simulation::apply_damping_zone (the same loop over DampingZone::factor)
//     timed alone on a copy of the velocities, once a step;
//   - a cross-check: whole steps with the paddle held still and with physics.damping_zone removed, run in
//     rounds interleaved with the full scene's (the fastest round of each; noisy on a shared machine).
// Timings only here, never in tests; asserts nothing.
//   bench_waves [--steps N] [--rounds R] [--threads 1,2] [SCENE.json ...]
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "physics/damping_zone.hpp"
#include "physics/pair_loop.hpp"
#include "scene/scene.hpp"
#include "sim/simulation.hpp"

using namespace varsph;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Seconds per step of each simulation: `rounds` rounds, each advancing every simulation by `steps` steps in
// turn (so that a change of the machine's load falls on all of them), the fastest round of each.
std::vector<double> interleaved(const std::vector<Simulation<2>*>& sims, int steps, int rounds) {
  std::vector<double> best(sims.size(), 1e300);
  for (auto* s : sims)
    for (int k = 0; k < 5; ++k) s->advance();  // warm-up
  for (int r = 0; r < rounds; ++r)
    for (std::size_t k = 0; k < sims.size(); ++k) {
      const auto t0 = Clock::now();
      for (int s = 0; s < steps; ++s) sims[k]->advance();
      best[k] = std::min(best[k], seconds_since(t0) / steps);
    }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  int steps = 50, rounds = 6;
  std::vector<int> threads = {1, 2};
  std::vector<std::string> scenes;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--steps" && k + 1 < argc) steps = std::atoi(argv[++k]);
    else if (a == "--rounds" && k + 1 < argc) rounds = std::atoi(argv[++k]);
    else if (a == "--threads" && k + 1 < argc) {
      threads.clear();
      for (char* t = std::strtok(argv[++k], ","); t; t = std::strtok(nullptr, ",")) threads.push_back(std::atoi(t));
    } else if (!a.empty() && a[0] != '-') scenes.push_back(a);
    else {
      std::fprintf(stderr, "usage: bench_waves [--steps N] [--rounds R] [--threads 1,2] [SCENE.json ...]\n");
      return 2;
    }
  }
  if (scenes.empty())
    for (const char* s : {"piston_flume_2d.json", "flap_flume_2d.json"})
      scenes.push_back(std::string(VARSPH_SOURCE_DIR) + "/pipelines/waves/" + s);
  for (const auto& file : scenes) {
    std::ifstream in(file);
    const nlohmann::json j = nlohmann::json::parse(in);
    int paddle = -1;
    for (std::size_t b = 0; b < j.at("bodies").size(); ++b)
      if (j["bodies"][b].contains("motion")) paddle = int(b);
    if (paddle < 0 || !j["physics"].contains("damping_zone")) {
      std::fprintf(stderr, "%s: no wavemaker or no physics.damping_zone\n", file.c_str());
      return 2;
    }
    nlohmann::json still = j, undamped = j;
    still["bodies"][std::size_t(paddle)].erase("motion");
    undamped["physics"].erase("damping_zone");
    for (int t : threads) {
      omp_set_num_threads(t);
      Simulation<2> sim(scene::parse_scene_json(j, file));
      Simulation<2> s_still(scene::parse_scene_json(still, file));
      Simulation<2> s_undamped(scene::parse_scene_json(undamped, file));
      const std::vector<double> per = interleaved({&sim, &s_still, &s_undamped}, steps, rounds);
      const double per_step = per[0];
      const std::size_t n = sim.size();
      // the paddle: move_boundaries at the current time (idempotent: the walls are already there)
      const int reps = 200;
      auto t0 = Clock::now();
      for (int r = 0; r < reps; ++r) sim.move_boundaries(sim.time());
      const double motion = 2 * seconds_since(t0) / reps;
      // the damping zone: Simulation::apply_damping_zone's loop on a copy of the velocities
      physics::DampingZone<2> z;
      Vec<2> to;
      const auto& sc = sim.scene();
      for (int a = 0; a < 2; ++a) {
        z.from[a] = Real(sc.damping_zone_from[std::size_t(a)]);
        to[a] = Real(sc.damping_zone_to[std::size_t(a)]);
      }
      z.length = (to - z.from).norm();
      z.normal = (to - z.from) / z.length;
      z.beta = Real(sc.damping_zone_beta);
      z.quadratic = sc.damping_zone_profile == "quadratic";
      std::vector<Vec<2>> v(sim.fields().v.data.begin(), sim.fields().v.data.end());
      const Vec<2>* x = sim.fields().x.data.data();
      const std::int32_t* kind = sim.fields().kind.data.data();
      const Real h = Real(sim.dt());
      t0 = Clock::now();
      for (int r = 0; r < reps; ++r)
        for_each_particle(n, [&](std::size_t i) {
          if (kind[i] == 0) v[i] *= z.factor(x[i], h);
        });
      const double damping = seconds_since(t0) / reps;
      std::printf("%s, threads %d: %zu particles, %d steps, %.2f ms/step (%.1f ns per particle-step); paddle motion "
                  "%.3f ms/step = %.2f %% of a step (%.2f ns per particle-step), damping zone %.3f ms/step = %.2f %% "
                  "(%.2f ns per particle-step); together %.2f %%. Cross-check, whole steps (fastest of %d rounds): "
                  "paddle held still %.2f ms/step (%+.2f %%), no damping zone %.2f ms/step (%+.2f %%)\n",
                  sc.name.c_str(), t, n, rounds * steps, 1e3 * per_step, 1e9 * per_step / double(n), 1e3 * motion,
                  100 * motion / per_step, 1e9 * motion / double(n), 1e3 * damping, 100 * damping / per_step,
                  1e9 * damping / double(n), 100 * (motion + damping) / per_step, rounds, 1e3 * per[1],
                  100 * (per[1] - per[0]) / per[0], 1e3 * per[2], 100 * (per[2] - per[0]) / per[0]);
      std::fflush(stdout);
    }
  }
  return 0;
}
