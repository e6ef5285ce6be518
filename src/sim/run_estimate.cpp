#include "sim/run_estimate.hpp"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sim/particle_budget.hpp"
#include "sim/simulation.hpp"
#include "sim/static_walls.hpp"

namespace varsph {
namespace {

// kB of a line of /proc/self/status ("VmRSS", "VmHWM"); 0 where there is none (not Linux)
double status_kb(const std::string& key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key + ":", 0) == 0) return std::atof(line.c_str() + key.size() + 1);
  return 0;
}

// frames of a run: t = 0, every output.every, and the last one at time.end when it is off that grid
double frame_count(const scene::Scene& s) {
  const double k = std::floor(s.t_end / s.output_every + 1e-9);
  return k + 1 + (s.t_end - k * s.output_every > 1e-9 * s.t_end ? 1 : 0);
}

// bytes one particle adds to a frame: its output arrays, its point and its vertex cell (8 + 8 + 1)
template <int D>
double frame_bytes_per_particle(const scene::Scene& s, const Simulation<D>& sim) {
  const double real = s.output_precision == "float64" ? 8 : 4;
  double b = 3 * real + 17;
  for (const auto& name : s.output_fields)
    if (const FieldBase* f = sim.store().find(name)) {
      const bool integer = f->scalar_type() == ScalarType::Int64 || f->scalar_type() == ScalarType::Int32;
      const double scalar = f->scalar_type() == ScalarType::Int64 ? 8 : f->scalar_type() == ScalarType::Int32 ? 4 : real;
      b += scalar * ((!integer && f->components() == D && D >= 2) ? 3 : f->components());
    }
  return b;
}

template <int D>
RunEstimate estimate(const scene::Scene& full, const scene::Scene& s, double k) {
  RunEstimate e;
  e.scaled = k > 1;
  e.coarsening = k;
  const double rss0 = status_kb("VmRSS");
  Simulation<D> sim(s);
  const auto& body = sim.fields().body.data;
  std::vector<double> per_body(s.bodies.size(), 0.0);
  for (std::size_t i = 0; i < sim.size(); ++i)
    if (std::size_t(body[i]) < per_body.size()) per_body[std::size_t(body[i])] += 1;
  // a coarser copy has k^d fewer particles in a volume and k^(d-1) fewer on a surface (walls of so many layers)
  for (std::size_t b = 0; b < per_body.size(); ++b) {
    const auto& spec = s.bodies[b];
    const bool volume = spec.kind == "fluid" || (spec.shape == "mesh" && spec.mesh.value("fill", "") == "volume");
    per_body[b] *= std::pow(k, volume ? D : D - 1);
    if (e.scaled && spec.shape != "mesh") per_body[b] = estimate_body_particles(full, b);  // from the box itself
    (spec.kind == "fluid" ? e.fluid : e.boundary) += per_body[b];
  }
  e.body_particles = per_body;
  const double n_built = double(sim.size()), n = e.fluid + e.boundary;
  // calibration: a few steps (the first one, which sets things up, not timed), at most about a second
  using clock = std::chrono::steady_clock;
  sim.advance();
  const auto t0 = clock::now();
  int steps = 0;
  while (steps < 30 && (steps < 3 || std::chrono::duration<double>(clock::now() - t0).count() < 1.0)) {
    sim.advance();
    ++steps;
  }
  const double secs = std::chrono::duration<double>(clock::now() - t0).count();
  e.calibration_steps = steps;
  e.threads = omp_get_max_threads();
  e.seconds_per_step = secs / std::max(steps, 1) * (n / std::max(n_built, 1.0));  // cost ~ particles
  const double dt = double(sim.dt()) * (full.dt ? 1.0 : 1.0 / k);  // a CFL step scales with h ~ dx
  e.steps = std::ceil(full.t_end / std::max(full.dt ? *full.dt : dt, 1e-300));
  // the resident size the built and stepped simulation added (neighbour grid and scratch included), at
  // least its particle arrays
  double arrays = 0;
  for (const auto& f : sim.store().fields()) arrays += double(f->bytes_per_particle());
  const double grown = std::max(0.0, status_kb("VmRSS") - rss0) * 1024.0 / std::max(n_built, 1.0);
  e.memory_bytes = std::max(grown, arrays) * n;
  // disk: every frame, the static walls once (output.static_boundary), two checkpoints kept
  e.frames = frame_count(full);
  const double per = frame_bytes_per_particle(full, sim);
  const auto is_static = static_bodies(full);
  double walls = 0, static_all = 0;
  for (std::size_t b = 0; b < per_body.size(); ++b)
    if (b < is_static.size() && is_static[b]) static_all += per_body[b];
  if (full.output_static_boundary == "once") walls = static_all;
  e.static_share = static_all / std::max(n, 1.0);
  constexpr double kHeader = 2700;  // a frame file's XML and array length words (measured: 2.6-2.7 kB)
  e.bytes_per_frame = per * (n - walls) + kHeader;
  e.bytes_static = walls > 0 ? per * walls + kHeader : 0;
  e.bytes_frames = e.frames * e.bytes_per_frame + e.bytes_static;
  double ckpt = 0;
  for (const auto& f : sim.store().fields())
    if (f->flags().checkpointed) ckpt += double(f->bytes_per_particle());
  e.bytes_checkpoint = ckpt * n;
  return e;
}

std::string human_bytes(double b) {
  char buf[48];
  if (b >= 1e9) std::snprintf(buf, sizeof buf, "%.3g GB", b / 1e9);
  else if (b >= 1e6) std::snprintf(buf, sizeof buf, "%.3g MB", b / 1e6);
  else std::snprintf(buf, sizeof buf, "%.3g kB", b / 1e3);
  return buf;
}

std::string human_seconds(double s) {
  char buf[48];
  if (s >= 3600) std::snprintf(buf, sizeof buf, "%.3g h", s / 3600);
  else if (s >= 60) std::snprintf(buf, sizeof buf, "%.3g min", s / 60);
  else std::snprintf(buf, sizeof buf, "%.3g s", s);
  return buf;
}

}  // namespace

template <int D>
std::string disk_estimate_line(const scene::Scene& s, const Simulation<D>& sim) {
  const auto& f = sim.fields();
  std::vector<std::uint32_t> walls, rest;
  split_static(f.kind.data, f.body.data, sim.size(), static_bodies(s), walls, rest);
  const bool once = s.output_static_boundary == "once";
  const double share = double(walls.size()) / double(std::max<std::size_t>(sim.size(), 1));
  const double per = frame_bytes_per_particle(s, sim), frames = frame_count(s);
  const double frame = per * double(once ? rest.size() : sim.size()) + 2700,
               stat = once && !walls.empty() ? per * double(walls.size()) + 2700 : 0;
  double ckpt = 0;
  for (const auto& fb : sim.store().fields())
    if (fb->flags().checkpointed) ckpt += double(fb->bytes_per_particle());
  ckpt *= double(sim.size());
  return "estimate: " + std::to_string(std::llround(frames)) + " frames x " + human_bytes(frame) +
         (stat > 0 ? " + the static walls once, " + human_bytes(stat) : std::string()) + " = " +
         human_bytes(frames * frame + stat) + " of frames, 2 checkpoints x " + human_bytes(ckpt) +
         " (varsph info estimates memory and time too)" +
         (!once && share > 0.5 ? "; static walls are " + std::to_string(std::llround(100 * share)) +
                                     " % of every frame: output.static_boundary = \"once\" writes them once"
                               : std::string());
}
template std::string disk_estimate_line<2>(const scene::Scene&, const Simulation<2>&);
template std::string disk_estimate_line<3>(const scene::Scene&, const Simulation<3>&);

RunEstimate estimate_run(const scene::Scene& s, const std::vector<std::string>& overrides,
                         const EstimateLimits& limits) {
  double planned = 0;
  for (std::size_t b = 0; b < s.bodies.size(); ++b) planned += estimate_body_particles(s, b);
  double k = 1;
  scene::Scene coarse = s;
  if (planned > limits.calibrate_max_particles) {  // too many to build in a second: a coarser copy
    k = std::pow(planned / limits.calibrate_max_particles, 1.0 / s.dimension);
    std::vector<std::string> o = overrides;
    o.push_back("particles.spacing=" + std::to_string(s.spacing * k));
    coarse = scene::parse_scene(s.file, o);
  }
  return s.dimension == 2 ? estimate<2>(s, coarse, k) : estimate<3>(s, coarse, k);
}

std::string describe_estimate(const scene::Scene& s, const RunEstimate& e, const EstimateLimits& limits,
                              std::vector<std::string>& warnings) {
  std::ostringstream o;
  o.precision(4);
  const std::string how = e.scaled ? " (scaled from a copy at " + std::to_string(e.coarsening).substr(0, 5) +
                                         " x dx: --calibrate-max)"
                                   : "";
  for (std::size_t b = 0; b < e.body_particles.size(); ++b)
    o << "body " << b << std::string(b < 10 ? 14 : 13, ' ') << s.bodies[b].kind << " " << s.bodies[b].shape
      << (s.bodies[b].shape == "mesh" && s.bodies[b].mesh.contains("mesh") && s.bodies[b].mesh["mesh"].is_string()
              ? " " + s.bodies[b].mesh["mesh"].get<std::string>()
              : std::string())
      << ": "
      << std::llround(e.body_particles[b]) << " particles" << (e.scaled ? " (estimate)" : "") << "\n";
  const double total = e.fluid + e.boundary;
  o << "estimate memory     " << human_bytes(e.memory_bytes) << " (" << std::llround(total) << " particles x "
    << std::llround(e.memory_bytes / std::max(total, 1.0)) << " bytes measured per particle)" << how << "\n"
    << "estimate steps      " << std::llround(e.steps) << (s.dt ? " (fixed dt)" : " (the CFL step after "
    + std::to_string(e.calibration_steps + 1) + " steps; it shrinks when the flow speeds up)") << "\n"
    << "estimate wall time  " << human_seconds(e.steps * e.seconds_per_step) << " (" << e.seconds_per_step * 1e3
    << " ms per step measured on " << e.threads << " thread(s) of this machine, now)" << how << "\n"
    << "estimate disk       " << human_bytes(e.bytes_frames) << " for " << std::llround(e.frames) << " frames ("
    << human_bytes(e.bytes_per_frame) << " each"
    << (e.bytes_static > 0 ? " + the static walls once, " + human_bytes(e.bytes_static) : std::string()) << "), "
    << human_bytes(2 * e.bytes_checkpoint) << " for the 2 checkpoints kept";
  if (s.output_static_boundary != "once" && e.static_share > 0.5)  // the torus user's 363 MB frames (issue 35)
    o << "; static walls are " << std::llround(100 * e.static_share) << " % of every frame: output.static_boundary "
      << "= \"once\" writes them once (" << human_bytes(e.frames * e.bytes_per_frame * (1 - e.static_share) +
                                                     e.bytes_per_frame * e.static_share) << ")";
  o << "\n";
  // limits: the user's, else this machine's memory and the free space where the run would go
  double mem_limit = limits.memory_gb * 1e9;
  if (!(mem_limit > 0)) mem_limit = 0.8 * double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
  double disk_limit = limits.disk_gb * 1e9;
  if (!(disk_limit > 0)) {
    std::error_code ec;
    disk_limit = double(std::filesystem::space(std::filesystem::current_path(), ec).available);
  }
  if (e.memory_bytes > mem_limit)
    warnings.push_back("estimate: memory " + human_bytes(e.memory_bytes) + " is above " + human_bytes(mem_limit) +
                       (limits.memory_gb > 0 ? " (--max-memory)" : " (80 % of this machine's memory; --max-memory)"));
  if (e.steps * e.seconds_per_step > limits.hours * 3600)
    warnings.push_back("estimate: wall time " + human_seconds(e.steps * e.seconds_per_step) + " is above " +
                       human_seconds(limits.hours * 3600) + " (--max-hours)");
  if (e.bytes_frames + 2 * e.bytes_checkpoint > disk_limit)
    warnings.push_back("estimate: disk " + human_bytes(e.bytes_frames + 2 * e.bytes_checkpoint) + " is above " +
                       human_bytes(disk_limit) +
                       (limits.disk_gb > 0 ? " (--max-disk)" : " (free here; --max-disk)") +
                       (s.output_static_boundary == "once" ? "" : "; output.static_boundary = \"once\" writes static walls once"));
  return o.str();
}

}  // namespace varsph
