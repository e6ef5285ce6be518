#include "sim/runner.hpp"

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <iostream>

#include <nlohmann/json.hpp>
#include <omp.h>

#include "core/errors.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_table.hpp"
#include "io/pvd_series.hpp"
#include "io/run_directory.hpp"
#include "sim/build_info.hpp"
#include "sim/diagnostics.hpp"
#include "sim/frame_export.hpp"
#include "sim/simulation.hpp"

namespace varsph {
namespace {

volatile std::sig_atomic_t g_signal = 0;
extern "C" void on_signal(int sig) { g_signal = sig; }

std::string iso_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

const std::vector<std::string> kDiagnosticColumns = {
    "frame", "step", "time", "dt", "momentum_x", "momentum_y", "momentum_z", "momentum_Q", "angular_momentum",
    "kinetic_energy", "potential_energy", "internal_energy", "max_speed", "density_error_max", "wall_seconds",
    "fp_iterations_mean", "fp_iterations_max", "fp_residual_max", "fp_contraction_max", "dt_bound"};

template <int D>
class Runner {
 public:
  Runner(const scene::Scene& s, const RunOptions& o) : scene_(s), opt_(o) {}

  int run() {
    using clock = std::chrono::steady_clock;
    if (opt_.threads > 0) omp_set_num_threads(opt_.threads);
    Simulation<D> sim(scene_);
    dir_ = io::prepare_run_directory(opt_.output_dir, scene_.name, opt_.overwrite, !opt_.restart.empty());
    pvd_ = std::make_unique<io::PvdSeries>(dir_.pvd());
    diag_.open(dir_.diagnostics(), kDiagnosticColumns);
    started_ = iso_now();
    t0_ = clock::now();
    write_run_json(sim, "running", "");

    const bool tty = isatty(STDOUT_FILENO) && !opt_.quiet;
    if (!opt_.quiet)
      std::printf("varsph: %s: %zu fluid + %zu boundary particles, dt %.3g s, to t = %g s -> %s\n",
                  scene_.name.c_str(), sim.count(0), sim.count(1), sim.dt(), scene_.t_end,
                  dir_.root.string().c_str());
    write_frame(sim);
    double next_frame = scene_.output_every;
    auto last_log = clock::now();
    std::string failure;
    int exit_code = kExitOk;
    const long start_step = sim.step();

    warn_dt_bound(sim.dt(), sim.integrator().dt_bound(), 0);  // on the initial state (eq. 54 estimate)
    while (sim.time() < scene_.t_end - 0.5 * sim.dt()) {
      StepReport rep;
      try {
        rep = sim.advance();
      } catch (const NumericalError& e) {  // e.g. a fixed point that did not converge (on_failure = fail)
        // the integrator left the state at the last accepted step: write it as the last good frame
        if (!last_frame_at_current_) write_frame(sim);
        failure = std::string(e.what()) + ". The last good frame is " + last_frame_name_;
        exit_code = kExitNumerical;
        break;
      }
      accumulate(rep);
      warn_dt_bound(sim.dt(), rep.dt_bound, sim.step());
      last_frame_at_current_ = false;
      if (const std::string bad = check_health(sim); !bad.empty()) {
        failure = "numerical failure at step " + std::to_string(sim.step()) + ", t = " + std::to_string(sim.time()) +
                  " s: " + bad + ". The last good frame is " + last_frame_name_;
        exit_code = kExitNumerical;
        break;
      }
      if (sim.time() >= next_frame - 0.5 * sim.dt()) {
        write_frame(sim);
        while (next_frame <= sim.time() + 0.5 * sim.dt()) next_frame += scene_.output_every;
      }
      const double wall = seconds_since(t0_);
      if (tty) {
        const double rate = double(sim.step() - start_step) / std::max(wall, 1e-9);
        const double eta = (scene_.t_end - sim.time()) / std::max(sim.dt(), 1e-300) / std::max(rate, 1e-9);
        std::printf("\r  t = %.4f / %.4f s   step %ld   %.0f steps/s   ETA %.0f s   ", sim.time(), scene_.t_end,
                    sim.step(), rate, eta);
        std::fflush(stdout);
      } else if (!opt_.quiet && (seconds_since(last_log) > 10.0 ||
                                 (scene_.log_every_steps > 0 && sim.step() % scene_.log_every_steps == 0))) {
        last_log = clock::now();
        std::printf("  t = %.4f / %.4f s, step %ld, %.1f s wall\n", sim.time(), scene_.t_end, sim.step(), wall);
        std::fflush(stdout);
      }
      if (const int sig = g_signal) {
        if (!last_frame_at_current_) write_frame(sim);
        failure = std::string("stopped by ") + (sig == SIGINT ? "SIGINT" : "SIGTERM") + " at step " +
                  std::to_string(sim.step()) + ", t = " + std::to_string(sim.time()) + " s; last frame " +
                  last_frame_name_;
        exit_code = sig == SIGINT ? kExitSigint : kExitSigterm;
        break;
      }
    }
    if (exit_code == kExitOk && !last_frame_at_current_) write_frame(sim);
    if (tty) std::printf("\n");
    const double wall = seconds_since(t0_);
    steps_ = sim.step() - start_step;
    particle_steps_ = double(steps_) * double(sim.count(0));
    write_run_json(sim, exit_code == kExitOk ? "completed" : (exit_code == kExitNumerical ? "failed" : "interrupted"),
                   failure);
    if (exit_code != kExitOk) {
      std::fprintf(stderr, "varsph: %s\n", failure.c_str());
      return exit_code;
    }
    if (!opt_.quiet)
      std::printf("varsph: done: %ld steps in %.2f s (%.1f ns per fluid particle-step); %s\n", steps_, wall,
                  wall / std::max(particle_steps_, 1.0) * 1e9, dir_.pvd().string().c_str());
    return kExitOk;
  }

 private:
  static double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  }

  void warn_dt_bound(double dt, double bound, long step) {
    if (bound <= 0 || dt <= bound || warned_dt_bound_) return;
    warned_dt_bound_ = true;
    std::fprintf(stderr,
                 "varsph: warning: dt = %.3g s exceeds the fixed-point bound of eq. (54), about %.3g s (step %ld); "
                 "the iterations may stop converging\n",
                 dt, bound, step);
  }

  void accumulate(const StepReport& r) {
    ++fp_steps_;
    fp_iter_sum_ += r.iterations;
    fp_iter_max_ = std::max(fp_iter_max_, r.iterations);
    fp_res_max_ = std::max(fp_res_max_, r.residual);
    fp_contr_max_ = std::max(fp_contr_max_, r.contraction);
    dt_bound_ = r.dt_bound;
  }

  void write_frame(Simulation<D>& sim) {
    const long index = frame_index_++;
    const io::FrameData fd = frame_from(sim, scene_.output_fields, scene_.output_precision == "float64");
    io::write_vtu(dir_.frame(index).string(), fd);
    pvd_->add(sim.time(), dir_.frame_relative(index));
    last_frame_name_ = dir_.frame_relative(index);
    last_frame_at_current_ = true;
    const Diagnostics d = compute_diagnostics(sim);
    using io::CsvTable;
    std::vector<std::string> row = {
        CsvTable::num(index), CsvTable::num(sim.step()), CsvTable::num(sim.time()), CsvTable::num(sim.dt()),
        CsvTable::num(d.momentum[0]), CsvTable::num(d.momentum[1]), CsvTable::num(d.momentum[2]),
        CsvTable::num(d.momentum_Q), CsvTable::num(d.angular_momentum), CsvTable::num(d.kinetic_energy),
        CsvTable::num(d.potential_energy), CsvTable::num(d.internal_energy), CsvTable::num(d.max_speed),
        CsvTable::num(d.density_error_max), CsvTable::num(seconds_since(t0_))};
    if (sim.integrator().implicit() && fp_steps_ > 0) {
      row.push_back(CsvTable::num(double(fp_iter_sum_) / double(fp_steps_)));
      row.push_back(CsvTable::num(long(fp_iter_max_)));
      row.push_back(CsvTable::num(fp_res_max_));
      row.push_back(CsvTable::num(fp_contr_max_));
      row.push_back(CsvTable::num(dt_bound_));
    } else {
      row.insert(row.end(), 5, "");
    }
    diag_.row(row);
    fp_steps_ = 0;
    fp_iter_sum_ = 0;
    fp_iter_max_ = 0;
    fp_res_max_ = fp_contr_max_ = 0;
  }

  void write_run_json(const Simulation<D>& sim, const std::string& status, const std::string& message) {
    nlohmann::json j;
    j["program"] = "varsph";
    j["version"] = VARSPH_VERSION;
    j["build"] = build_info();
    j["command_line"] = opt_.command_line;
    j["scene_file"] = scene_.file.string();
    j["scene"] = scene_.resolved;
    j["resolved"] = {{"dimension", D},           {"dx", scene_.spacing},
                     {"h", scene_.h},            {"support_radius", double(sim.rates().support())},
                     {"kernel", kernels::to_string(scene_.kernel)},
                     {"c0", scene_.c0},          {"c0_rule", scene_.c0_rule},
                     {"B", double(sim.eos().B)}, {"fluid_particles", sim.count(0)},
                     {"boundary_particles", sim.count(1)}};
    j["started"] = started_;
    j["status"] = status;
    if (!message.empty()) j["message"] = message;
    if (status != "running") {
      const double wall = seconds_since(t0_);
      j["finished"] = iso_now();
      j["timings"] = {{"wall_seconds", wall},
                      {"steps", steps_},
                      {"simulated_seconds", sim.time()},
                      {"fluid_particle_steps_per_second", particle_steps_ / std::max(wall, 1e-9)},
                      {"ns_per_fluid_particle_step", wall / std::max(particle_steps_, 1.0) * 1e9},
                      {"threads", omp_get_max_threads()}};
    }
    io::write_text_atomically(dir_.run_json(), j.dump(2) + "\n");
  }

  const scene::Scene& scene_;
  RunOptions opt_;
  io::RunDirectory dir_;
  std::unique_ptr<io::PvdSeries> pvd_;
  io::CsvTable diag_;
  std::string started_, last_frame_name_ = "(none)";
  std::chrono::steady_clock::time_point t0_;
  long frame_index_ = 0, steps_ = 0;
  bool last_frame_at_current_ = false;
  bool warned_dt_bound_ = false;
  double particle_steps_ = 0;
  long fp_steps_ = 0, fp_iter_sum_ = 0;
  int fp_iter_max_ = 0;
  double fp_res_max_ = 0, fp_contr_max_ = 0, dt_bound_ = 0;
};

}  // namespace

void install_signal_handlers() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}
int pending_signal() { return g_signal; }

int run_scene(const scene::Scene& scene, const RunOptions& options) {
  if (scene.dimension == 2) return Runner<2>(scene, options).run();
  return Runner<3>(scene, options).run();
}

}  // namespace varsph
