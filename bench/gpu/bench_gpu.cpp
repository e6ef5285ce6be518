// Speed of the device backend on DualSPHysics' 3D dam break (pipelines/dam_break_3d_dsph.json), against
// DualSPHysics 5.4 on an H100 (issue 14; docs/gpu.md). Timings only here, never in tests.
//   bench_gpu [--device cuda|cpu|cuda_emulation] [--dp 0.0085,0.004,0.002] [--steps N] [--threads N]
//             [--paper] [--tiny] [--engineering] [--set KEY=VALUE]...
// Per case: particles, mean neighbours, ms per step, particle-steps/s (fluid, and fluid + boundary as
// DualSPHysics counts them), pair interactions/s, bytes per particle on the device (the mirror with its
// grid, sort and pass buffers; the last-good copy the runner keeps for blow-up handling separately).
// --paper: the paper's 2D dam break (1682 particles, 10^4 steps of 1e-4 s) timed end to end (goal < 1 s).
// --tiny: a 20 mm case of ~10^4 particles (the host launch prints sane numbers on it in seconds).
// --engineering: the same dam break with the README's recommended set-up (the kernel, fluid, physics, boundary,
// integrator and health blocks of pipelines/engineering_3d.json, read from that file: Riemann solver, dummy
// walls, Wendland C2, symplectic Euler) and 3 wall layers for the dummy walls (DualSPHysics' case has 1); its
// "x DSPH" column stays 0 (another method than the reference's).
// Each step is the runner's: advance() plus the health check (a reduction on the device).
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "core/source_dir.hpp"
#include "exec/device_backend.hpp"
#include "exec/device_run.hpp"
#include "scene/json_reader.hpp"
#include "scene/scene.hpp"
#include "sim/diagnostics.hpp"
#include "sim/simulation.hpp"

using namespace varsph;

namespace {

// DualSPHysics 5.4, 3D CaseDambreak on one H100 (issue 14): dp, fluid + boundary particles, particle-steps/s
struct Reference {
  double dp;
  const char* particles;
  double steps_per_s;
  const char* memory;
};
const Reference kDualSPHysics[] = {{0.0085, "128,310 + 43,186", 1.46e8, "27 MiB"},
                                   {0.004, "1,228,400 + 193,984", 2.65e8, "223 MiB"},
                                   {0.002, "10,020,000 + 777,136", 2.75e8, "1.69 GiB"}};

double reference_for(double dp) {
  for (const auto& r : kDualSPHysics)
    if (std::abs(r.dp - dp) < 1e-9) return r.steps_per_s;
  return 0;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Mean neighbours of fluid particles and pair interactions of one step over every particle that sums pairs
// (fluid and dynamic walls), from the host grid after a download.
template <int D>
std::pair<double, double> neighbours(Simulation<D>& sim) {
  sim.sync_host();
  const auto& g = sim.grid();
  const auto& x = sim.fields().x.data;
  const Real rc2 = sim.rates().support() * sim.rates().support();
  const bool walls = sim.params().boundary == physics::BoundaryModel::Dynamic;
  double fluid_pairs = 0, all_pairs = 0;
  std::size_t n = 0;
  for (const auto& b : g.blocks())
    for (std::uint32_t i = b.begin; i < b.end; ++i) {
      const bool fluid = sim.fields().kind[i] == 0;
      if (!fluid && !walls) continue;
      double c = 0;
      for (std::uint32_t r = b.nbr_begin; r < b.nbr_end; ++r) {
        const auto nr = g.ranges()[r];
        for (std::uint32_t j = nr.begin; j < nr.end; ++j) c += (j != i && (x[i] - g.shift(nr.shift) - x[j]).squaredNorm() < rc2);
      }
      all_pairs += c;
      if (fluid) {
        fluid_pairs += c;
        ++n;
      }
    }
  return {n ? fluid_pairs / double(n) : 0, all_pairs};
}

template <int D>
void one_step(Simulation<D>& sim) {
  sim.advance();
  if (sim.on_device()) {
    if (sim.device()->first_unhealthy() >= 0) {
      std::fprintf(stderr, "bench_gpu: %s\n", exec::check_device_health(sim).c_str());
      std::exit(3);
    }
  } else if (const std::string bad = check_health(sim); !bad.empty()) {
    std::fprintf(stderr, "bench_gpu: %s\n", bad.c_str());
    std::exit(3);
  }
}

// --engineering's overrides: pipelines/engineering_3d.json's method blocks, and wall layers for dummy walls
std::vector<std::string> engineering_sets() {
  const auto j = scene::read_json_file(source_dir_or(VARSPH_SOURCE_DIR) + "/pipelines/engineering_3d.json");
  std::vector<std::string> o;
  for (const char* k : {"kernel", "fluid", "physics", "boundary", "integrator", "health"})
    if (j.contains(k)) o.push_back(std::string(k) + "=" + j.at(k).dump());
  o.push_back("bodies.1.layers=3");  // the tank
  o.push_back("bodies.2.layers=3");  // the obstacle
  return o;
}

void run_dam_break(const std::string& device, double dp, int steps, const std::vector<std::string>& sets,
                   bool engineering) {
  // particles.max_count: the scene's default guard (1e7) would refuse DualSPHysics' finest size (10.8 M at dp 0.002)
  std::vector<std::string> o = {"particles.spacing=" + std::to_string(dp), "execution.device=\"" + device + "\"",
                                "particles.max_count=5e7"};
  o.insert(o.end(), sets.begin(), sets.end());
  const auto s = scene::parse_scene(source_dir_or(VARSPH_SOURCE_DIR) + "/pipelines/dam_break_3d_dsph.json", o);
  const auto t_setup = std::chrono::steady_clock::now();
  Simulation<3> sim(s);
  const double setup = seconds_since(t_setup);
  one_step(sim);  // warm-up: the first sort moves everything, the device allocates its sort scratch
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k) one_step(sim);
  const double sec = seconds_since(t0);
  const double nf = double(sim.count(0)), nall = double(sim.size());
  const auto [nb, all_pairs] = neighbours(sim);
  const double ps_all = nall * steps / sec;
  const double ref = engineering ? 0.0 : reference_for(dp);
  double state_b = 0, snap_b = 0;
  if (sim.on_device()) {
    state_b = double(sim.device()->state_bytes()) / nall;
    snap_b = double(sim.device()->snapshot_bytes()) / nall;
  }
  std::printf("%-15s %7.4f %10.0f %9.0f %6.1f %9.3f %10.3g %10.3g %10.3g %8.1f %8.1f %7.1f %8.2f\n", device.c_str(), dp,
              nf, nall - nf, nb, sec / steps * 1e3, nf * steps / sec, ps_all, all_pairs * steps / sec, state_b, snap_b,
              setup, ref > 0 ? ps_all / ref : 0.0);
  std::fflush(stdout);
}

void run_paper(const std::string& device, const std::vector<std::string>& sets) {
  std::vector<std::string> o = {"execution.device=\"" + device + "\""};
  o.insert(o.end(), sets.begin(), sets.end());
  const auto s = scene::parse_scene(source_dir_or(VARSPH_SOURCE_DIR) + "/pipelines/dam_break_2d_paper.json", o);
  Simulation<2> sim(s);
  const int steps = int(std::lround(s.t_end / *s.dt));
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k) one_step(sim);
  const double sec = seconds_since(t0);
  std::printf("paper 2D dam break on %s: %zu fluid + %zu boundary particles, %d steps of %g s in %.3f s "
              "(goal: < 1 s), %.3g fluid particle-steps/s\n",
              device.c_str(), sim.count(0), sim.count(1), steps, *s.dt, sec, double(sim.count(0)) * steps / sec);
}

}  // namespace

int main(int argc, char** argv) {
  std::string device = "cuda";
  std::vector<double> dps = {0.0085, 0.004, 0.002};
  std::vector<std::string> sets;
  int steps = 50, threads = 0;
  bool paper = false, tiny = false, engineering = false;
  for (int k = 1; k < argc; ++k) {
    const bool more = k + 1 < argc;
    if (!std::strcmp(argv[k], "--help") || !std::strcmp(argv[k], "-h")) {
      std::printf("bench_gpu [--device cuda|cpu|cuda_emulation] [--dp 0.0085,0.004,0.002] [--steps N] [--threads N]\n"
                  "          [--paper] [--tiny] [--engineering] [--set KEY=VALUE]...   (docs/gpu.md)\n");
      return 0;
    }
    if (!std::strcmp(argv[k], "--device") && more) device = argv[++k];
    else if (!std::strcmp(argv[k], "--steps") && more) steps = std::max(1, std::atoi(argv[++k]));
    else if (!std::strcmp(argv[k], "--threads") && more) threads = std::max(1, std::atoi(argv[++k]));
    else if (!std::strcmp(argv[k], "--set") && more) sets.push_back(argv[++k]);
    else if (!std::strcmp(argv[k], "--paper")) paper = true;
    else if (!std::strcmp(argv[k], "--tiny")) tiny = true;
    else if (!std::strcmp(argv[k], "--engineering")) engineering = true;
    else if (!std::strcmp(argv[k], "--dp") && more) {
      dps.clear();
      for (char* t = argv[++k]; *t;) {
        char* end = nullptr;
        dps.push_back(std::strtod(t, &end));
        if (end == t) break;
        t = *end == ',' ? end + 1 : end;
      }
    } else {
      std::fprintf(stderr, "bench_gpu: unknown argument '%s' (see --help)\n", argv[k]);
      return 2;
    }
  }
  if (threads > 0) omp_set_num_threads(threads);
  if (std::string why; device == "cuda" && !exec::cuda_device_present(&why)) {
    std::printf("bench_gpu: skipped: no CUDA device (%s)\n", why.c_str());
    return 77;  // CTest's SKIP_RETURN_CODE
  }
  if (tiny) dps = {0.02};
  try {
    std::printf("# varsph %s (%s), %s build; device %s", VARSPH_VERSION, VARSPH_REAL_NAME, VARSPH_BUILD_TYPE,
                device.c_str());
    if (device == "cuda") std::printf(" (%s)", exec::cuda_device_description().c_str());
    if (device != "cuda") std::printf(", %d OpenMP threads", omp_get_max_threads());
    std::printf("\n# DualSPHysics 5.4 on an H100, same case (particle-steps/s over fluid + boundary):");
    for (const auto& r : kDualSPHysics) std::printf(" dp %g: %s, %.3g/s, %s;", r.dp, r.particles, r.steps_per_s, r.memory);
    std::printf("\n");
    if (paper) {
      run_paper(device, sets);
      return 0;
    }
    if (engineering) {
      std::vector<std::string> e = engineering_sets();
      std::printf("# set-up: engineering (pipelines/engineering_3d.json's method blocks, 3 wall layers)\n");
      e.insert(e.end(), sets.begin(), sets.end());
      sets = e;
    }
    std::printf("%-15s %7s %10s %9s %6s %9s %10s %10s %10s %8s %8s %7s %8s\n", "device", "dp", "fluid", "boundary",
                "neighb", "ms/step", "fluid p-s/s", "all p-s/s", "pairs/s", "B/p dev", "B/p copy", "setup s",
                "x DSPH");
    for (double dp : dps) run_dam_break(device, dp, tiny ? std::min(steps, 5) : steps, sets, engineering);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_gpu: %s\n", e.what());
    return 2;
  }
  return 0;
}
