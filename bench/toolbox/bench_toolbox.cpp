// Times the paper dam break (pipelines/dam_break_2d_paper.json) for N Verlet steps and prints
// ns per particle-step, for the scene as it is (no toolbox term named) and with toolbox terms named
// via --set overrides. Built against any version of varsph_core (only the Simulation API is used), so
// the same source measures the code before the toolbox. Never asserts timings.
//   bench_toolbox [steps] [repeats] [--set KEY=VALUE ...]
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "sim/simulation.hpp"

using namespace varsph;

int main(int argc, char** argv) {
  int steps = 500, repeats = 3;
  std::vector<std::string> overrides;
  std::vector<std::string> pos;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--set" && k + 1 < argc) overrides.push_back(argv[++k]);
    else pos.push_back(a);
  }
  if (pos.size() > 0) steps = std::atoi(pos[0].c_str());
  if (pos.size() > 1) repeats = std::atoi(pos[1].c_str());
  const auto file = std::string(VARSPH_SOURCE_DIR) + "/pipelines/dam_break_2d_paper.json";
  double best = 1e300, best_cpu = 1e300;  // wall and process CPU time (CPU time is steadier on a shared machine)
  std::size_t n = 0;
  for (int r = 0; r < repeats; ++r) {
    Simulation<2> sim(scene::parse_scene(file, overrides));
    n = sim.count(0);
    for (int k = 0; k < 20; ++k) sim.advance();  // warm-up
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    for (int k = 0; k < steps; ++k) sim.advance();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    best = std::min(best, s);
    best_cpu = std::min(best_cpu, double(std::clock() - c0) / CLOCKS_PER_SEC);
  }
  const double ps = double(steps) * double(n);
  std::printf("dam_break_2d_paper: %zu fluid particles, %d steps, best of %d: %.1f ns (wall), %.1f ns (CPU) per fluid "
              "particle-step",
              n, steps, repeats, 1e9 * best / ps, 1e9 * best_cpu / ps);
  for (auto& o : overrides) std::printf(" [%s]", o.c_str());
  std::printf("\n");
  return 0;
}
