// Speed of the solver step on the foundation cases (issue "Foundation", section Speed; issue
// "Performance"): ns per fluid particle-step, fluid particle-steps/s, pair interactions/s and mean
// neighbours, for 1 and 2 threads. Timings only here, never in tests.
//   bench_step [--quick] [--case NAME]
//   bench_step --scene FILE [--set KEY=VALUE]... [--steps N] [--threads 1,2] [--repeats R]
//       one scene of your own (pipelines/bench_flatness.py uses it for the cost-per-particle curve); the
//       best (minimum) of R repeats per thread count is printed. Every line ends with the process's peak
//       resident size so far (getrusage ru_maxrss) in MB.
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <utility>
#include <string>
#include <vector>

#include "core/source_dir.hpp"
#include "scene/scene.hpp"
#include "sim/simulation.hpp"

using namespace varsph;

namespace {

struct Case {
  std::string name, scene;
  std::vector<std::string> overrides;
  int steps;
};

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

// Mean neighbours of the fluid particles, and the pair interactions of one step over all particles that
// run a pair sum (fluid, plus dynamic walls, which integrate their density: DualSPHysics counts those too).
template <int D>
std::pair<double, double> neighbours(const Simulation<D>& sim) {
  const auto& g = sim.grid();
  const auto& x = sim.fields().x.data;
  const Real rc2 = sim.rates().support() * sim.rates().support();
  const bool walls_active = sim.params().boundary == physics::BoundaryModel::Dynamic;
  double fluid_pairs = 0, all_pairs = 0;
  std::size_t n = 0;
  for (const auto& b : g.blocks())
    for (std::uint32_t i = b.begin; i < b.end; ++i) {
      const bool fluid = sim.fields().kind[i] == 0;
      if (!fluid && !walls_active) continue;
      double cnt = 0;
      for (std::uint32_t r = b.nbr_begin; r < b.nbr_end; ++r) {
        const auto nr = g.ranges()[r];
        for (std::uint32_t j = nr.begin; j < nr.end; ++j)
          cnt += (j != i && (x[i] - g.shift(nr.shift) - x[j]).squaredNorm() < rc2);
      }
      all_pairs += cnt;
      if (fluid) {
        fluid_pairs += cnt;
        ++n;
      }
    }
  return {n ? fluid_pairs / double(n) : 0, all_pairs};
}

template <int D>
void run_case(const scene::Scene& s, const Case& c, const std::vector<int>& thread_counts, int repeats) {
  for (int threads : thread_counts) {
    omp_set_num_threads(threads);
    Simulation<D> sim(s);
    sim.advance();  // warm-up (first sort moves everything)
    double sec = std::numeric_limits<double>::infinity();
    long iterations = 0;  // fixed-point iterations of an implicit scheme, over all timed steps
    for (int r = 0; r < repeats; ++r) {  // the state advances between repeats: same cost per step
      const auto t0 = std::chrono::steady_clock::now();
      for (int k = 0; k < c.steps; ++k) iterations += sim.advance().iterations;
      sec = std::min(sec, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    const double ps = double(c.steps) * double(sim.count(0));
    const auto [nb, all_pairs] = neighbours(sim);
    std::printf("%-30s %9zu %8zu %3d %7.1f %10.1f %9.3f %9.1f %10.2f %9.1f %9.1f %6s %6.2f\n", c.name.c_str(),
                sim.count(0), sim.count(1), threads, nb, sec / ps * 1e9, ps / sec * 1e-6, ps * nb / sec * 1e-6,
                sec / c.steps * 1e3, peak_rss_mb(), all_pairs * c.steps / sec * 1e-6, sim.rates().simd(),
                double(iterations) / double(repeats * c.steps));
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string only, scene_file;
  std::vector<std::string> sets;
  std::vector<int> thread_counts = {1, 2};
  int steps = 0, repeats = 1;
  for (int k = 1; k < argc; ++k) {
    const bool more = k + 1 < argc;
    if (!std::strcmp(argv[k], "--help") || !std::strcmp(argv[k], "-h")) {
      std::printf(
          "bench_step [--quick] [--case NAME]        the built-in cases (NAME: substring of a case name)\n"
          "bench_step --scene FILE [--set KEY=VALUE]... [--steps N] [--threads 1,2] [--repeats R]\n"
          "--set applies scene overrides to the built-in cases too; --case NAME alone when a case has that name\n"
          "columns: ns per fluid particle-step, fluid particle-steps/s, fluid pairs/s (fluid x mean neighbours),\n"
          "ms per step, peak RSS (MB), all pairs/s (fluid + dynamic walls, as DualSPHysics counts), pair sweep\n"
          "(scalar, avx2, avx512: VARSPH_SIMD=auto|scalar|avx2|avx512 in the environment picks it), mean\n"
          "fixed-point iterations per step (variational integrator; 0 for explicit schemes)\n");
      return 0;
    }
    if (!std::strcmp(argv[k], "--quick")) quick = true;
    else if (!std::strcmp(argv[k], "--case") && more) only = argv[++k];
    else if (!std::strcmp(argv[k], "--scene") && more) scene_file = argv[++k];
    else if (!std::strcmp(argv[k], "--set") && more) sets.push_back(argv[++k]);
    else if (!std::strcmp(argv[k], "--steps") && more) steps = std::atoi(argv[++k]);
    else if (!std::strcmp(argv[k], "--repeats") && more) repeats = std::max(1, std::atoi(argv[++k]));
    else if (!std::strcmp(argv[k], "--threads") && more) {
      thread_counts.clear();
      for (const char* t = argv[++k]; *t;) {
        char* end = nullptr;
        thread_counts.push_back(std::max(1, int(std::strtol(t, &end, 10))));
        t = *end == ',' ? end + 1 : end;
        if (end == t && *t) break;
      }
    } else {
      std::fprintf(stderr, "bench_step: unknown argument '%s' (see --help)\n", argv[k]);
      return 2;
    }
  }
  const std::string dir = source_dir_or(VARSPH_SOURCE_DIR) + "/pipelines/";
  std::vector<Case> cases = {
      {"dam_break_2d_paper_1682", "dam_break_2d_paper.json", {}, quick ? 200 : 2000},
      {"dam_break_2d_27k", "dam_break_2d_paper.json", {"particles.spacing=0.00125", "integrator.dt=2.5e-5"}, quick ? 20 : 200},
      {"dam_break_2d_430k", "dam_break_2d_paper.json", {"particles.spacing=0.0003125", "integrator.dt=6e-6"}, quick ? 3 : 20},
      {"box_3d_100k", "bench_box_3d.json", {}, quick ? 3 : 20},
      // the kernel and h of DualSPHysics' 3D dam break (cubic spline, h = 1.732 dp: ~166 neighbours)
      {"box_3d_100k_cubic_h1.73", "bench_box_3d.json", {"kernel.type=\"cubic_spline\"", "kernel.h_over_dx=1.732"},
       quick ? 2 : 10},
      {"dsph_val_2d_20k", "dam_break_2d_dsph_val.json", {}, quick ? 20 : 200},
      // the same with the paper's Verlet (eq. 60-62: continuity at the new configuration, two sweeps a step)
      {"dsph_val_2d_20k_paper_verlet", "dam_break_2d_dsph_val.json", {"integrator.type=\"verlet\""}, quick ? 20 : 200},
  };
  std::printf("# varsph %s (%s), %s build\n", VARSPH_VERSION, VARSPH_REAL_NAME, VARSPH_BUILD_TYPE);
  std::printf("%-30s %9s %8s %3s %7s %10s %9s %9s %10s %9s %9s %6s %6s\n", "case", "fluid", "boundary", "thr",
              "neighb", "ns/p-step", "Mp-step/s", "Mpair/s", "ms/step", "peakMB", "Mpair/s*", "sweep", "fp_it");
  if (!scene_file.empty()) {
    cases = {{"custom", scene_file, sets, steps > 0 ? steps : 5}};
    only.clear();
  } else {
    for (auto& c : cases) {
      if (steps > 0) c.steps = steps;
      c.overrides.insert(c.overrides.end(), sets.begin(), sets.end());
    }
  }
  bool exact = false;  // --case NAME picks that case alone when a case has exactly that name
  for (const auto& c : cases) exact = exact || c.name == only;
  for (const auto& c : cases) {
    if (!only.empty() && (exact ? c.name != only : c.name.find(only) == std::string::npos)) continue;
    const auto s = scene::parse_scene(c.scene.front() == '/' || !scene_file.empty() ? c.scene : dir + c.scene,
                                      c.overrides);
    if (s.dimension == 2) run_case<2>(s, c, thread_counts, repeats);
    else run_case<3>(s, c, thread_counts, repeats);
  }
}
