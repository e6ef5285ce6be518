#include "sim/runner.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <iostream>

#include <nlohmann/json.hpp>
#include <omp.h>

#include "core/errors.hpp"
#include "bodies/body_table.hpp"
#include "exec/device_run.hpp"
#include "io/atomic_file.hpp"
#include "io/checkpoint.hpp"
#include "io/csv_table.hpp"
#include "io/pvd_series.hpp"
#include "io/run_directory.hpp"
#include "parallel/collective.hpp"
#include "parallel/communicator.hpp"
#include "parallel/domain.hpp"
#include "parallel/run_output.hpp"
#include "sim/build_info.hpp"
#include "sim/diagnostics.hpp"
#include "sim/frame_export.hpp"
#include "sim/run_estimate.hpp"
#include "sim/static_walls.hpp"
#include "sim/health.hpp"
#include "sim/open_boundaries.hpp"
#include "sim/probes.hpp"
#include "sim/restart.hpp"
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
    "fp_iterations_mean", "fp_iterations_max", "fp_residual_max", "fp_contraction_max", "dt_bound",
    // health.* (sim/health.hpp): fluid particles now, and removed since the start per rule
    "fluid_particles", "removed_domain", "removed_density", "removed_speed",
    // slowest rank's busy time over the mean (1 in one process; docs/parallel.md)
    "imbalance",
    // open boundaries and the mass balance (sim/open_boundaries.hpp; Simulation::flow()), appended last:
    // particles created at inlets and removed at outlets since the start, buffer particles now, fluid mass
    // in and out since the start (out: outlets and health removals), fluid mass in the domain now, and
    // mass_in - mass_out - (fluid_mass - fluid_mass at t = 0), which closes to round-off
    "particles_created", "removed_outlet", "buffer_particles", "mass_in", "mass_out", "fluid_mass", "mass_balance",
    // rigid bodies (issue 30; zeros without them): their momentum, kinetic and potential energy (sim/diagnostics.hpp)
    "bodies_momentum_x", "bodies_momentum_y", "bodies_momentum_z", "bodies_kinetic_energy", "bodies_potential_energy"};

const std::vector<std::string> kRemovedColumns = {
    "time", "step", "id", "rule", "x", "y", "z", "vx", "vy", "vz", "density", "pressure", "fluid_neighbours",
    "boundary_neighbours"};

template <int D>
class Runner {
 public:
  Runner(const scene::Scene& s, const RunOptions& o)
      : scene_(s), opt_(o), comm_(o.comm ? o.comm : std::make_shared<parallel::SerialCommunicator>()),
        root_(comm_->root()), quiet_(o.quiet || !comm_->root()), health_(s) {}

  int run() {
    using clock = std::chrono::steady_clock;
    if (opt_.threads > 0) omp_set_num_threads(opt_.threads);
    // a restart checkpoint is read and validated before the run directory is touched (exit 2, nothing
    // overwritten)
    std::optional<io::Checkpoint> ckpt;
    auto& comm = *comm_;
    if (!opt_.restart.empty())  // each rank reads its share of the rows (all of them in one process)
      parallel::collectively(comm, [&] { ckpt = io::read_checkpoint(opt_.restart, comm.rank(), comm.size()); });
    Simulation<D> sim(scene_, comm_);
    Probes<D> probes(scene_);
    if (ckpt) {
      restore_from_checkpoint(sim, *ckpt, opt_.restart.string());
      ckpt->arrays = {};  // the header (runner state) is still needed; the particle copy is not
    }
    parallel::collectively(comm, [&] {  // rank 0 prepares the directory; an error stops every rank
      if (root_) dir_ = io::prepare_run_directory(opt_.output_dir, scene_.name, opt_.overwrite, !opt_.restart.empty());
    });
    if (!root_) dir_ = io::RunDirectory{opt_.output_dir, scene_.name};
    dir_.pieces = comm.size() > 1;
    started_ = iso_now();
    t0_ = clock::now();
    last_checkpoint_wall_ = t0_;
    try {
      return run_loop(sim, probes, ckpt ? &*ckpt : nullptr);
    } catch (const IoError& e) {
      // best effort: the disk may be full or the directory gone
      try {
        write_run_json(sim, "failed", std::string("I/O error: ") + e.what());
      } catch (const std::exception&) {
      }
      throw;
    }
  }

 private:
  int run_loop(Simulation<D>& sim, Probes<D>& probes, const io::Checkpoint* ckpt) {
    using clock = std::chrono::steady_clock;
    probes_ = &probes;
    open_outputs(sim, probes, ckpt);
    write_run_json(sim, "running", "");

    const bool tty = isatty(STDOUT_FILENO) && !quiet_;
    if (!quiet_) {
      std::printf("varsph: %s: %zu fluid + %zu boundary particles, dt %.3g s, to t = %g s -> %s\n",
                  scene_.name.c_str(), sim.count(0), sim.count(1), sim.dt(), scene_.t_end,
                  dir_.root.string().c_str());
      std::printf("varsph: %s\n", disk_estimate_line(scene_, sim).c_str());  // issue 35: before the disk fills
      if (ckpt)
        std::printf("varsph: restarting from %s (step %ld, t = %.9g s)\n", opt_.restart.string().c_str(), sim.step(),
                    sim.time());
    }
    if (!ckpt) {
      write_frame(sim);
      if (!probes.empty()) write_probes(sim, probes);
      if (auto* rb = sim.rigid_bodies()) {
        rb->evaluate_loads(sim);  // the loads of the initial state (the state itself is not changed)
        write_bodies(sim);
      }
    }
    auto last_log = clock::now();
    std::string failure;
    int exit_code = kExitOk;
    const long start_step = sim.step();

    warn_dt_bound(sim.dt(), sim.integrator().dt_bound(), 0);  // on the initial state (eq. 54 estimate)
    while (sim.time() < scene_.t_end - 0.5 * sim.dt()) {
      capture_last_good(sim);
      if (deferred_.frame || deferred_.checkpoint) {  // the last step's outputs go to the host during this one
        sim.device()->begin_snapshot_download();
        deferred_.started = true;
      }
      StepReport rep;
      try {
        const auto t_step = clock::now();
        // the health check's per-particle pass runs inside the step's parallel region where there is one
        rep = sim.advance([&] {
          if (!sim.on_device()) health_.flag_pass(sim);
        });
        step_seconds_ += seconds_since(t_step);
      } catch (const NumericalError& e) {  // e.g. a fixed point that did not converge (on_failure = fail)
        // the integrator left the state at the last accepted step: write it as the last good frame and
        // checkpoint
        flush_deferred(sim);
        if (!last_frame_at_current_) write_frame(sim);
        const std::string cp = write_checkpoint(sim);
        failure = std::string(e.what()) + ". The last good frame is " + last_frame_name_ + ", checkpoint " + cp;
        exit_code = kExitNumerical;
        break;
      }
      flush_deferred(sim);  // writes the previous step's frame / checkpoint (device runs)
      accumulate(rep);
      warn_dt_bound(sim.dt(), rep.dt_bound, sim.step());
      last_frame_at_current_ = false;
      if (const std::string bad = sim.on_device() ? device_health(sim) : health_.after_step(sim); !bad.empty()) {  // agreed by every rank
        failure = handle_blow_up(sim, bad);
        exit_code = kExitNumerical;
        break;
      }
      if (!health_.last_removed().empty()) write_removed();
      if (sim.time() >= next_frame_ - 0.5 * sim.dt()) {
        if (deferrable(sim)) defer(sim, /*frame=*/true);
        else write_frame(sim);
        while (next_frame_ <= sim.time() + 0.5 * sim.dt()) next_frame_ += scene_.output_every;
      }
      // point queries (pressure probes) read ghosts: their density and pressure are the owners' of the
      // last pass, not of the step's end (one exchange per step, distributed runs with probes only)
      if (!probes.empty() && sim.distributed()) sim.refresh_halo(sim.current_view());
      if (!probes.empty()) {  // load probes integrate over their interval
        if (sim.on_device() && has_load_probes()) sim.sync_host();  // they read the state every step
        probes.accumulate(sim);
      }
      if ((!probes.empty() || sim.rigid_bodies()) && sim.time() >= next_probe_ - 0.5 * sim.dt()) {
        if (!probes.empty()) write_probes(sim, probes);
        write_bodies(sim);
        if (scene_.probes_every > 0)
          while (next_probe_ <= sim.time() + 0.5 * sim.dt()) next_probe_ += scene_.probes_every;
      }
      if (checkpoint_due(sim)) {
        if (deferrable(sim)) defer(sim, /*frame=*/false);
        else write_checkpoint(sim);
      }
      const double wall = seconds_since(t0_);
      if (tty) {
        const double rate = double(sim.step() - start_step) / std::max(wall, 1e-9);
        const double eta = (scene_.t_end - sim.time()) / std::max(sim.dt(), 1e-300) / std::max(rate, 1e-9);
        std::printf("\r  t = %.4f / %.4f s   step %ld   %.0f steps/s   ETA %.0f s   ", sim.time(), scene_.t_end,
                    sim.step(), rate, eta);
        std::fflush(stdout);
      } else if (!quiet_ && (seconds_since(last_log) > 10.0 ||
                                 (scene_.log_every_steps > 0 && sim.step() % scene_.log_every_steps == 0))) {
        last_log = clock::now();
        std::printf("  t = %.4f / %.4f s, step %ld, %.1f s wall\n", sim.time(), scene_.t_end, sim.step(), wall);
        std::fflush(stdout);
      }
      // a signal on any rank stops every rank after the same step
      if (const int sig = comm_->size() > 1 ? int(comm_->max(double(g_signal))) : int(g_signal)) {
        // the step is finished: write a frame and a checkpoint of it, then stop
        flush_deferred(sim);
        if (!last_frame_at_current_) write_frame(sim);
        const std::string cp = write_checkpoint(sim);
        failure = std::string("stopped by ") + (sig == SIGINT ? "SIGINT" : "SIGTERM") + " at step " +
                  std::to_string(sim.step()) + ", t = " + std::to_string(sim.time()) + " s; last frame " +
                  last_frame_name_ + ", checkpoint " + cp + " (continue with --restart " + cp + ")";
        exit_code = sig == SIGINT ? kExitSigint : kExitSigterm;
        break;
      }
    }
    flush_deferred(sim);
    if (exit_code == kExitOk) {
      if (!last_frame_at_current_) write_frame(sim);
      write_checkpoint(sim);
    }
    if (tty) std::printf("\n");
    const double wall = seconds_since(t0_);
    steps_ = sim.step() - start_step;
    particle_steps_ = double(steps_) * double(sim.count(0));
    write_run_json(sim, exit_code == kExitOk ? "completed" : (exit_code == kExitNumerical ? "failed" : "interrupted"),
                   failure);
    if (exit_code != kExitOk) {
      if (root_) std::fprintf(stderr, "varsph: %s\n", failure.c_str());
      return exit_code;
    }
    if (!quiet_)
      std::printf("varsph: done: %ld steps in %.2f s (%.1f ns per fluid particle-step); %s%s\n", steps_, wall,
                  wall / std::max(particle_steps_, 1.0) * 1e9, dir_.pvd().string().c_str(), removal_summary().c_str());
    return kExitOk;
  }

  static double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  }

  // --- outputs and restart ------------------------------------------------------------------------
  // Opens the .pvd, diagnostics.csv and probes.csv. A restart in the run's own directory keeps what
  // was written up to the checkpoint time and drops what came after (frames, rows, later checkpoints);
  // schedules (frame numbering, next output times) continue from the checkpoint's runner state.
  void open_outputs(Simulation<D>& sim, Probes<D>& probes, const io::Checkpoint* ckpt) {
    pvd_ = std::make_unique<io::PvdSeries>(dir_.pvd());
    next_frame_ = scene_.output_every;
    next_probe_ = scene_.probes_every;
    next_checkpoint_ = scene_.checkpoint_every;
    double keep_up_to = -1;
    if (ckpt) {
      const auto& rs = ckpt->header.runner_state;
      const double t = sim.time(), half = 0.5 * sim.dt();
      const auto resume = [&](const char* next_key, const char* every_key, double every, double& next) {
        if (rs.contains(next_key) && rs.contains(every_key) && rs.at(every_key).get<double>() == every) {
          next = rs.at(next_key).get<double>();
        } else if (every > 0) {  // the rate changed on restart: the first multiple after t
          next = every * std::floor(t / every);
          while (next <= t + half) next += every;
        }
      };
      resume("next_frame", "output_every", scene_.output_every, next_frame_);
      resume("next_probe", "probes_every", scene_.probes_every, next_probe_);
      resume("next_checkpoint", "checkpoint_every", scene_.checkpoint_every, next_checkpoint_);
      frame_index_ = rs.value("frame_index", 0L);
      if (rs.contains("probe_window")) probes.restore_state(rs.at("probe_window"));
      const auto& fp = rs.value("fp", nlohmann::json::object());
      fp_steps_ = fp.value("steps", 0L);
      fp_iter_sum_ = fp.value("iter_sum", 0L);
      fp_iter_max_ = fp.value("iter_max", 0);
      fp_res_max_ = fp.value("res_max", 0.0);
      fp_contr_max_ = fp.value("contr_max", 0.0);
      dt_bound_ = fp.value("dt_bound", 0.0);
      last_checkpoint_step_ = sim.step();
      if (in_own_directory()) {
        keep_up_to = sim.time();
        pvd_->load();
        pvd_->truncate_after(keep_up_to + io::kFrameTimeDrift);  // .pvd times are rounded (pvd_series.hpp)
        on_root([&] {
          pvd_->write();
          drop_later_files(sim.step());
        });
      }
      last_frame_name_ = "(none since the restart)";
    }
    on_root([&] {  // rank 0 writes the tables
      diag_.open(dir_.diagnostics(), kDiagnosticColumns, keep_up_to);
      removed_csv_.open(dir_.removed(), kRemovedColumns, keep_up_to);
      if (!probes.empty()) {
        std::vector<std::string> cols = {"time"};
        for (auto& c : probes.columns()) cols.push_back(c);
        probes_csv_.open(dir_.probes(), cols, keep_up_to);
      }
      if (sim.rigid_bodies()) {
        bodies_csv_.open(dir_.bodies(), bodies::body_columns(), keep_up_to);
        if (!sim.rigid_bodies()->moorings().empty())
          moorings_csv_.open(dir_.moorings(), bodies::mooring_columns(), keep_up_to);
      }
    });
    if (ckpt && ckpt->header.runner_state.contains("health"))
      health_.restore_state(ckpt->header.runner_state.at("health"));
    else
      health_.start(sim);  // collective in a distributed run
  }

  bool in_own_directory() const {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path from = fs::weakly_canonical(fs::absolute(opt_.restart), ec).parent_path().parent_path();
    return fs::equivalent(from, dir_.root, ec);
  }

  // Restart in the run's own directory: frames numbered from the checkpoint's next frame on and
  // checkpoints of later steps belong to the replaced future.
  void drop_later_files(long step) {
    namespace fs = std::filesystem;
    std::error_code ec;
    for (const auto& [s, p] : io::list_checkpoints(dir_.checkpoints()))
      if (s > step) io::remove_checkpoint(p);
    for (long k = frame_index_;; ++k) {  // .vtu or .pvtu: the run may have had another number of ranks
      io::RunDirectory other = dir_;
      other.pieces = !dir_.pieces;
      if (!fs::exists(dir_.frame(k), ec) && !fs::exists(other.frame(k), ec)) break;
      dir_.remove_frame(k);
      other.remove_frame(k);
    }
  }

  // pressure and force probes read the state every step (Probes::accumulate)
  bool has_load_probes() const {
    for (const auto& p : scene_.probes)
      if (p.is_object() && (p.value("type", "") == "pressure" || p.value("type", "") == "force")) return true;
    return false;
  }
  nlohmann::json runner_state() const {
    nlohmann::json j = runner_clock_state();
    if (probes_ && !probes_->empty()) j["probe_window"] = probes_->save_state();
    return j;
  }
  nlohmann::json runner_clock_state() const {
    return {{"frame_index", frame_index_},
            {"next_frame", next_frame_},
            {"output_every", scene_.output_every},
            {"next_probe", next_probe_},
            {"probes_every", scene_.probes_every},
            {"next_checkpoint", next_checkpoint_},
            {"checkpoint_every", scene_.checkpoint_every},
            {"health", health_.save_state()},
            {"fp",
             {{"steps", fp_steps_},
              {"iter_sum", fp_iter_sum_},
              {"iter_max", fp_iter_max_},
              {"res_max", fp_res_max_},
              {"contr_max", fp_contr_max_},
              {"dt_bound", dt_bound_}}}};
  }

  // --- checkpoints --------------------------------------------------------------------------------
  bool checkpoint_due(const Simulation<D>& sim) {
    bool due = false;
    if (scene_.checkpoint_every_steps > 0 && sim.step() % scene_.checkpoint_every_steps == 0) due = true;
    if (scene_.checkpoint_every > 0 && sim.time() >= next_checkpoint_ - 0.5 * sim.dt()) {
      due = true;
      while (next_checkpoint_ <= sim.time() + 0.5 * sim.dt()) next_checkpoint_ += scene_.checkpoint_every;
    }
    if (scene_.checkpoint_wall_minutes > 0) {
      bool late = seconds_since(last_checkpoint_wall_) >= 60.0 * scene_.checkpoint_wall_minutes;
      if (comm_->size() > 1) late = comm_->max(late ? 1.0 : 0.0) > 0;  // rank clocks differ: agree
      due = due || late;
    }
    return due;
  }

  // Writes DIR/checkpoints/step_N.h5 atomically and keeps the last two; returns its path.
  std::string write_checkpoint(Simulation<D>& sim) {
    const auto path = dir_.checkpoints() / io::checkpoint_file_name(sim.step());
    const bool exists = comm_->size() > 1 ? comm_->max(std::filesystem::exists(path) ? 1.0 : 0.0) > 0
                                          : std::filesystem::exists(path);
    if (last_checkpoint_step_ != sim.step() || !exists) {
      sim.sync_host();  // a device run's state into the store
      write_checkpoint_of(sim, checkpoint_header(sim, runner_state()));
    }
    return path.string();
  }
  // The store as it is, under `h` (its step names the file); keeps the last two. Collective.
  void write_checkpoint_of(Simulation<D>& sim, const io::CheckpointHeader& h) {
    const auto path = dir_.checkpoints() / io::checkpoint_file_name(h.step);
    {
      parallel::write_checkpoint(*comm_, path, h, sim.store(), sim.size());
      last_checkpoint_step_ = h.step;
      last_checkpoint_wall_ = std::chrono::steady_clock::now();
      if (root_) {
        auto all = io::list_checkpoints(dir_.checkpoints());
        for (std::size_t k = 0; k + 2 < all.size(); ++k) io::remove_checkpoint(all[k].second);
      }
    }
  }

  // --- device runs: a step's frame and checkpoint are copied to the host while the next step runs ------
  // (the runner's last-good copy on the device holds exactly that state during the next step;
  // docs/gpu.md). Frames whose fields are all checkpointed qualify; others are downloaded at once.
  bool deferrable(const Simulation<D>& sim) const {
    if (!sim.on_device()) return false;
    for (const auto& name : scene_.output_fields)
      if (const FieldBase* f = sim.store().find(name); !f || !f->flags().checkpointed) return false;
    return true;
  }
  void defer(Simulation<D>& sim, bool frame) {
    if (frame) {
      deferred_.frame = true;
      deferred_.frame_index = frame_index_++;  // reserved now: checkpoints of this step count it
      deferred_.time = sim.time();
      deferred_.step = sim.step();
      deferred_.dt = sim.dt();
    } else {
      deferred_.checkpoint = true;
      deferred_.header = checkpoint_header(sim, runner_state());
    }
  }
  void flush_deferred(Simulation<D>& sim) {
    if (!deferred_.frame && !deferred_.checkpoint) return;
    if (deferred_.started) sim.device()->finish_snapshot_download();
    else sim.sync_host();  // still the same step: the current state is the deferred one
    Deferred d = std::move(deferred_);
    deferred_ = {};
    if (d.frame) write_frame_at(sim, d.frame_index, d.time, d.step, d.dt);
    if (d.checkpoint) write_checkpoint_of(sim, d.header);
  }

  // --- the health rules on a device run -------------------------------------------------------------
  // The device tests every particle as flag_pass does (a reduction, no download); only a step with a
  // flagged particle brings the state to the host, where the rules decide as on the CPU (remove and count,
  // or stop the run), and the survivors go back to the device. Spray is rare, so the copies are too.
  std::string device_health(Simulation<D>& sim) {
    if (sim.device()->first_unhealthy() < 0) {
      health_.clean_step(sim.step());
      return {};
    }
    sim.sync_host();
    const std::string bad = health_.after_step(sim);
    if (bad.empty() && !health_.last_removed().empty()) sim.host_state_changed();
    return bad;
  }

  // --- blow-up handling ---------------------------------------------------------------------------
  // The state is copied into preallocated buffers every kLastGoodEvery steps (cost in run.json:
  // timings.last_good_copy_seconds); a failing step is undone by restoring the copy and replaying the
  // steps after it, which reproduces the last good step exactly (StateSnapshot::replay_to).
  static constexpr long kLastGoodEvery = 100;
  // Device runs copy on the device every step (cheap there): the deferred outputs download that copy.
  void capture_last_good(Simulation<D>& sim) {
    if (!sim.on_device() && last_good_.valid() && sim.step() - last_good_.step() < kLastGoodEvery &&
        sim.step() >= last_good_.step())
      return;
    const auto t = std::chrono::steady_clock::now();
    last_good_.capture(sim, runner_state());
    snapshot_seconds_ += seconds_since(t);
  }

  std::string handle_blow_up(Simulation<D>& sim, const std::string& bad) {
    const long bad_step = sim.step();
    const double bad_time = sim.time();
    std::string msg = "numerical failure at step " + std::to_string(bad_step) + ", t = " + std::to_string(bad_time) +
                      " s: " + bad + ".";
    if (!last_good_.valid()) return msg;
    last_good_.replay_to(sim, bad_step - 1);
    if (last_frame_step_ != sim.step()) write_frame(sim);
    const std::string cp = write_checkpoint(sim);
    return msg + " Wrote the last good state (step " + std::to_string(sim.step()) + ", t = " +
           std::to_string(sim.time()) + " s): frame " + last_frame_name_ + ", checkpoint " + cp;
  }

  // --- particles removed by the health rules ------------------------------------------------------
  // One removed.csv row per particle; the first removal of each rule is also reported on stderr.
  void write_removed() {  // every rank holds the same list (HealthMonitor gathers it); rank 0 writes
    on_root([&] { write_removed_rows(); });
  }
  void write_removed_rows() {
    using io::CsvTable;
    for (const RemovedParticle& p : health_.last_removed()) {
      removed_csv_.row({CsvTable::num(p.time), CsvTable::num(p.step), CsvTable::num(long(p.id)),
                        removal_rule_name(p.rule), CsvTable::num(p.x[0]), CsvTable::num(p.x[1]), CsvTable::num(p.x[2]),
                        CsvTable::num(p.v[0]), CsvTable::num(p.v[1]), CsvTable::num(p.v[2]), CsvTable::num(p.rho),
                        CsvTable::num(p.p), CsvTable::num(long(p.fluid_neighbours)),
                        CsvTable::num(long(p.boundary_neighbours))});
      bool& warned = warned_removal_[std::size_t(p.rule)];
      if (warned) continue;
      warned = true;
      std::fprintf(stderr,
                   "varsph: warning: step %ld, t = %.6g s: removed fluid particle id %lld (health rule '%s': density "
                   "%.6g kg/m^3, speed %.4g m/s, %d fluid neighbours); further removals are counted in "
                   "diagnostics.csv and listed in removed.csv\n",
                   p.step, p.time, static_cast<long long>(p.id), removal_rule_name(p.rule), p.rho,
                   std::sqrt(p.v[0] * p.v[0] + p.v[1] * p.v[1] + p.v[2] * p.v[2]), p.fluid_neighbours);
    }
  }

  std::string removal_summary() const {
    if (health_.removed_total() == 0) return "";
    const auto& r = health_.removed();
    return "; removed " + std::to_string(health_.removed_total()) + " of " + std::to_string(health_.initial_fluid()) +
           " fluid particles (domain " + std::to_string(r[0]) + ", density " + std::to_string(r[1]) + ", speed " +
           std::to_string(r[2]) + "; removed.csv)";
  }

  // --- per-frame and per-sample output ------------------------------------------------------------
  void write_probes(Simulation<D>& sim, Probes<D>& probes) {
    flush_deferred(sim);
    sim.sync_host();  // probes read the store (a device run copies its state back first)
    std::vector<std::string> row = {io::CsvTable::num(sim.time())};
    for (double v : probes.sample(sim)) row.push_back(io::CsvTable::num(v));  // collective
    on_root([&] { probes_csv_.row(row); });
  }

  // bodies.csv and moorings.csv rows of the state after the last step (rigid bodies only)
  void write_bodies(Simulation<D>& sim) {
    const auto* rb = sim.rigid_bodies();
    if (!rb) return;
    on_root([&] {
      for (const auto& row : bodies::body_rows(*rb, sim.time())) bodies_csv_.row(row);
      if (moorings_csv_.is_open())
        for (const auto& row : bodies::mooring_rows(*rb, sim.time())) moorings_csv_.row(row);
    });
  }

  void warn_dt_bound(double dt, double bound, long step) {
    if (bound <= 0 || dt <= bound || warned_dt_bound_) return;
    warned_dt_bound_ = true;
    if (!root_) return;  // the same warning on every rank: rank 0 prints it
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

  // output.static_boundary = "once" (one process): the frame `fd` leaves the static walls out and names the
  // file that holds them, written now when there is none yet from this process or their number changed
  // (a restart writes its own at its first frame). Returns that file relative to the run directory.
  std::string lean_frame(Simulation<D>& sim, io::FrameData& fd, long index) {
    const auto& f = sim.fields();
    split_static(f.kind.data, f.body.data, sim.size(), static_bodies(scene_), static_sel_, moving_sel_);
    if (static_rel_.empty() || static_sel_.size() != static_count_) {
      char num[32];
      std::snprintf(num, sizeof num, "%06ld", index);
      const std::string file = scene_.name + "_static_" + num + ".vtu";
      io::FrameData st = fd;
      st.select = &static_sel_;
      io::write_vtu((dir_.frames() / file).string(), st);
      static_rel_ = "frames/" + file;
      static_count_ = static_sel_.size();
    }
    fd.select = &moving_sel_;
    fd.static_file = std::filesystem::path(static_rel_).filename().string();  // beside the frame
    return static_rel_;
  }

  void write_frame(Simulation<D>& sim) {
    sim.sync_host();  // a device run's state into the store
    const long index = frame_index_++;
    write_frame_at(sim, index, sim.time(), sim.step(), sim.dt());
  }
  // Frame `index` and its diagnostics row from the store, which holds the state of (time, step, dt).
  void write_frame_at(Simulation<D>& sim, long index, double time, long step, double dt) {
    io::FrameData fd = frame_from(sim, scene_.output_fields, scene_.output_precision == "float64");
    fd.time = time;
    fd.step = step;
    fd.count = sim.size();  // owned particles (a piece per rank when distributed)
    const std::string static_rel = scene_.output_static_boundary == "once" ? lean_frame(sim, fd, index) : "";
    const std::string rel = parallel::write_frame(*comm_, dir_, index, fd);
    on_root([&] { pvd_->add(io::frame_time_label(time, scene_.output_every), rel, static_rel); });  // the deferred frame's time
    last_frame_name_ = dir_.frame_relative(index);
    last_frame_at_current_ = true;
    last_frame_step_ = step;
    const Diagnostics d = compute_diagnostics(sim);
    using io::CsvTable;
    std::vector<std::string> row = {
        CsvTable::num(index), CsvTable::num(step), CsvTable::num(time), CsvTable::num(dt),
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
    row.push_back(CsvTable::num(long(sim.count(0))));
    for (const long c : health_.removed()) row.push_back(CsvTable::num(c));
    // slowest rank's busy time over the mean since the previous row (1 in one process; collective)
    row.push_back(CsvTable::num(sim.distributed() ? sim.domain()->imbalance_since_last_report() : 1.0));
    {
      const FlowBalance& fl = sim.flow();
      const double m = sim.fluid_mass();  // collective
      row.push_back(CsvTable::num(fl.created));
      row.push_back(CsvTable::num(fl.removed_outlet));
      row.push_back(CsvTable::num(long(sim.open_boundaries() ? sim.open_boundaries()->buffer_count() : 0)));
      row.push_back(CsvTable::num(fl.mass_in));
      row.push_back(CsvTable::num(fl.mass_out()));
      row.push_back(CsvTable::num(m));
      row.push_back(CsvTable::num(fl.mass_in - fl.mass_out() - (m - fl.mass0)));
    }
    for (const double p : d.bodies_momentum) row.push_back(CsvTable::num(p));
    row.push_back(CsvTable::num(d.bodies_kinetic_energy));
    row.push_back(CsvTable::num(d.bodies_potential_energy));
    on_root([&] { diag_.row(row); });
    fp_steps_ = 0;
    fp_iter_sum_ = 0;
    fp_iter_max_ = 0;
    fp_res_max_ = fp_contr_max_ = 0;
  }

  // Work only rank 0 does (the run's single files), with its errors agreed on by every rank.
  template <class F>
  void on_root(F&& f) {
    parallel::collectively(*comm_, [&] {
      if (root_) f();
    });
  }

  // Ranks, threads and the decomposition's counters (summed over ranks) for run.json.
  nlohmann::json parallel_summary(Simulation<D>& sim) {
    nlohmann::json p = {{"ranks", comm_->size()}, {"threads_per_rank", omp_get_max_threads()}};
    if (auto* d = sim.domain()) {
      const auto& st = d->stats();
      double v[4] = {double(st.repartitions), double(st.migrated), double(st.halo_bytes_sent), double(st.rebins)};
      comm_->sum(v);
      p["repartitions"] = std::int64_t(v[0]) / comm_->size();
      p["particles_migrated"] = std::int64_t(v[1]);
      p["halo_bytes_sent"] = v[2];
      p["rebins"] = std::int64_t(v[3]) / comm_->size();
      p["max_particles_per_rank"] = comm_->max(double(sim.size()));
      // the surface-to-volume law of the halo (docs/performance.md "Beyond one machine")
      p["ghost_particles"] = std::int64_t(comm_->sum(double(sim.ghosts())));
      p["max_ghost_particles_per_rank"] = comm_->max(double(sim.ghosts()));
      p["max_halo_bytes_sent_per_rank"] = comm_->max(double(st.halo_bytes_sent));
      p["halo_refreshes"] = st.refreshes;
      // overlap of the halo refresh with the interior sweep (docs/parallel.md "Overlap")
      p["overlapped_refreshes"] = st.overlapped_refreshes;
      p["max_refresh_wait_seconds"] = comm_->max(st.refresh_wait_seconds);
      p["mean_refresh_wait_seconds"] = comm_->sum(st.refresh_wait_seconds) / comm_->size();
      p["max_rebin_wait_seconds"] = comm_->max(st.rebin_wait_seconds);
      p["interior_particles"] = std::int64_t(comm_->sum(double(st.interior_particles)));
      // the active absorption's gauge: readings whose column of particles ranks shared (gathered in serial order)
      if (sim.motion().absorbing())
        p["absorption_gauge_split_readings"] = std::int64_t(comm_->max(double(sim.split_column_readings())));
      // the partition's weights at the end (the same on every rank; refitted from cost in mode "cost")
      const auto& o = d->options();
      p["weights"] = {{"mode", o.weights_by_cost ? "cost" : "count"}, {"fluid", o.fluid_weight},
                      {"boundary", o.boundary_weight}, {"fits", st.weight_fits}};
    }
    return p;
  }

  void write_run_json(Simulation<D>& sim, const std::string& status, const std::string& message) {
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
    j["health"] = health_.report();
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
                      {"threads", omp_get_max_threads()},
                      {"pair_sweep", sim.rates().simd()},
                      {"last_good_copy_seconds", snapshot_seconds_},
                      {"step_seconds", step_seconds_},
                      {"last_good_every_steps", kLastGoodEvery},
                      {"last_good_copy_bytes", last_good_.bytes()}};
    }
    j["parallel"] = parallel_summary(sim);  // collective
    on_root([&] { io::write_text_atomically(dir_.run_json(), j.dump(2) + "\n"); });
  }

  const scene::Scene& scene_;
  RunOptions opt_;
  std::shared_ptr<parallel::Communicator> comm_;
  bool root_ = true, quiet_ = false;
  io::RunDirectory dir_;
  std::unique_ptr<io::PvdSeries> pvd_;
  std::vector<std::uint32_t> static_sel_, moving_sel_;  // lean frames: the static walls and the rest
  std::string static_rel_;                             // the static walls' file ("" = none written yet)
  std::size_t static_count_ = 0;
  Probes<D>* probes_ = nullptr;  // the run loop's probes (their accumulation goes into checkpoints)
  io::CsvTable diag_, probes_csv_, removed_csv_;
  io::CsvTable bodies_csv_, moorings_csv_;  // rigid bodies (bodies/body_table.hpp)
  HealthMonitor<D> health_;
  std::array<bool, kRemovalRules> warned_removal_{};
  double next_frame_ = 0, next_probe_ = 0, next_checkpoint_ = 0;
  long last_checkpoint_step_ = -1, last_frame_step_ = -1;
  std::chrono::steady_clock::time_point last_checkpoint_wall_;
  StateSnapshot<D> last_good_;
  double snapshot_seconds_ = 0;
  double step_seconds_ = 0;  // wall time inside Simulation::advance (no output, health or snapshot)
  std::string started_, last_frame_name_ = "(none)";
  std::chrono::steady_clock::time_point t0_;
  long frame_index_ = 0, steps_ = 0;
  bool last_frame_at_current_ = false;
  struct Deferred {
    bool frame = false, checkpoint = false, started = false;
    long frame_index = 0, step = 0;
    double time = 0, dt = 0;
    io::CheckpointHeader header;
  };
  Deferred deferred_;  // device runs: the outputs of the last step, written during the next
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
