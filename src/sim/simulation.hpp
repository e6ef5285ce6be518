#pragma once
// A scene resolved into one self-contained value: particle store, neighbour grid, the compiled physics
// passes and the integrator. Nothing global: several simulations can live in one process.
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/particle_store.hpp"
#include "neighbors/neighbor_grid.hpp"
#include "physics/eos.hpp"
#include "physics/particle_view.hpp"
#include "physics/physics_params.hpp"
#include "physics/rates.hpp"
#include "scene/scene.hpp"
#include "physics/damping_zone.hpp"
#include "sim/boundary_motion.hpp"
#include "sim/particle_fields.hpp"

namespace varsph {

namespace parallel {
class Communicator;
template <int D>
class Domain;
}  // namespace parallel

template <int D>
class Simulation;
template <int D>
class OpenBoundaries;
namespace bodies {
template <int D>
class RigidBodies;
}  // namespace bodies
namespace exec {
template <int D>
class DeviceRun;
template <int D>
class DeviceBackend;
}  // namespace exec

// Per-step integrator statistics (the fixed-point columns of diagnostics.csv for implicit schemes).
struct StepReport {
  int iterations = 0;         // fixed-point iterations (0 for explicit schemes)
  double residual = 0;        // final max_i |q_{k+1;j} - q_{k+1;j-1}| [m]
  double contraction = 0;     // largest observed r_j / r_{j-1}
  double dt_bound = 0;        // eq. (54) estimate [s], 0 if not applicable
};

template <int D>
class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual const char* name() const = 0;
  virtual bool implicit() const { return false; }
  // Current estimate of the largest dt for which the scheme's fixed point contracts (seed eq. 54) [s];
  // 0 when not applicable.
  virtual double dt_bound() const { return 0; }
  // Called once after the particles are built and binned (e.g. v(-1/2) of seed eq. 60).
  virtual void initialize(Simulation<D>& sim) = 0;
  // Advances the simulation by one step of length dt (chosen by the simulation's dt control).
  virtual StepReport step(Simulation<D>& sim) = 0;
  // True when step() follows core/team.hpp's rules (shared state written only in team_single or by the
  // loop helpers), so the simulation may run it inside one parallel region (issue 19: no fork per loop).
  virtual bool one_region_step() const { return false; }
  // Scalar state later steps depend on beyond the registered particle fields (e.g. a dt controller's
  // memory, a halving schedule), saved in checkpoints so a restarted run is bitwise identical.
  virtual nlohmann::json save_state() const { return nlohmann::json::object(); }
  virtual void restore_state(const nlohmann::json&) {}
};

// Particle and mass flows of a run since its start (diagnostics.csv; saved in checkpoints). "Fluid" here
// is the fluid in the domain: kind 0 particles that are not in an open boundary's buffer.
struct FlowBalance {
  long created = 0;               // particles created at inlets
  long removed_outlet = 0;        // buffer particles removed at outlets
  double mass_in = 0;             // mass that became fluid (inlet buffer particles crossing the interface) [kg]
  double mass_out_outlet = 0;     // fluid mass that entered an outlet buffer [kg]
  double mass_out_health = 0;     // fluid mass removed by the health rules [kg]
  double mass0 = 0;               // fluid mass at t = 0 [kg]
  double mass_out() const { return mass_out_outlet + mass_out_health; }
};

// Creates the integrator a scene names (InputError for names this build does not offer).
template <int D>
std::unique_ptr<Integrator<D>> make_integrator(const scene::Scene& s);

template <int D>
class Simulation {
 public:
  // `comm`: the ranks of a distributed run (parallel/session.hpp); null or one rank runs the serial code.
  explicit Simulation(const scene::Scene& scene, std::shared_ptr<parallel::Communicator> comm = nullptr);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  const scene::Scene& scene() const { return scene_; }
  ParticleStore& store() { return store_; }
  const ParticleStore& store() const { return store_; }
  ParticleFields<D>& fields() { return f_; }
  const ParticleFields<D>& fields() const { return f_; }
  const NeighborGrid<D>& grid() const { return grid_; }
  const physics::Rates<D>& rates() const { return *rates_; }
  const physics::PhysicsParams<D>& params() const { return params_; }
  const physics::TaitEos& eos() const { return eos_; }
  Integrator<D>& integrator() { return *integrator_; }

  double time() const { return time_; }
  long step() const { return step_; }
  double dt() const { return dt_; }
  std::size_t count(std::int32_t kind) const;
  // Particles this process owns (all of them in one process): integrators and reductions loop over
  // [0, size()); a distributed run keeps ghost copies of other ranks' particles after them in the store.
  std::size_t size() const { return store_.size() - ghosts(); }
  std::size_t ghosts() const;

  // One step of the integrator; updates time, step and the step report.
  const StepReport& advance();
  // The same, then after_step() on the new state: inside the step's parallel region when the step runs in
  // one (so a per-particle check costs no fork/join of its own; it must follow core/team.hpp's rules), else
  // right after. Skipped into the region only when nothing else changes the state after the step.
  const StepReport& advance(const std::function<void()>& after_step);
  const StepReport& last_report() const { return report_; }

  // --- services for integrators -----------------------------------------------------------------
  // Wraps periodic positions, sorts all particle arrays by cell (through the registry) and rebuilds
  // the neighbour grid. Moving walls and, within a step, open-boundary buffer particles take their
  // prescribed places first, so the grid is the grid of the step's final positions. `extra_skin` enlarges the cells so the grid stays valid while particles move
  // less than extra_skin / 2 (the variational iterations reuse it).
  void sort_and_bin();
  // The same without moving walls: wraps, sorts and bins the particles where they are.
  void rebin();
  // Extra shift applied to position-like fields (previous positions) when wrapping periodically.
  void register_position_like(Field<Vec<D>>* f) { position_like_.push_back(f); }
  void set_skin(Real skin);
  Real skin() const { return skin_; }
  // View of the current state (positions, velocities, densities, pressures).
  physics::ParticleView<D> current_view() const;
  void update_pressure();                  // p = EOS(rho) for every particle
  // What extrapolated wall models read about boundary particles (normals, interface distance, a_w).
  physics::WallGeometry<D> wall_geometry() const;
  void update_density_after_move(Real dt);  // continuity (rho += dt drho) or summation, then pressure
  // XSPH (physics.xsph): whether named, and the correction of the current state into the registered
  // field `xsph_velocity` (integrators drift with x += dt (v + correction)).
  bool xsph_enabled() const { return xsph_ != nullptr; }
  Vec<D>* compute_xsph();
  // Particle shifting (physics.shifting): moves fluid particles by dr = -D grad C (physics/shifting.hpp)
  // for the current dt. Call right after sort_and_bin() in the drift (the grid is built with a skin of
  // 2 max_shift dx, so it stays valid for the shifted positions); no-op when the scene does not name it.
  void apply_shifting();
  bool shifting_enabled() const { return rates_->shifting_enabled(); }
  // dt for the next step from the scene's fixed dt or CFL rule, given the last accelerations.
  double choose_dt() const;
  void set_dt(double dt) {
    team_single([&] { dt_ = dt; });  // every thread of a step region calls it
  }
  // Whether the next step runs in one OpenMP parallel region (core/team.hpp, sim/step_region.hpp).
  bool steps_in_one_region() const;
  // Positions and velocities of moving boundary bodies at time t, and of rigid bodies at their current
  // state (no-op when no body moves).
  void move_boundaries(double t);
  // The prescribed motions (wavemakers; their active absorption's state, sim/boundary_motion.hpp).
  const BoundaryMotion<D>& motion() const { return *motion_; }
  // The active absorption's state for checkpoints (an empty array when no paddle absorbs) and its restore.
  nlohmann::json save_motion_state() const { return motion_->save_state(); }
  void restore_motion_state(const nlohmann::json& j) { motion_->restore_state(j); }
  // The free-surface level [m] on the vertical line at horizontal position x (3D: across position y): the highest
  // level where the fluid indicator sum_j (m_j / rho_j) W crosses 1/2, sampled every dx/4 from the bed of the
  // scene's fluid (the water_height probe's definition, docs/results.md), over the fluid in the serial storage
  // order: one process's bits on any thread count and, distributed, on any number of ranks (each rank's owned
  // particles near the line are gathered to every rank and summed in order-tag order). Collective when
  // distributed (every rank calls it with the same line); the active absorption's gauge.
  double free_surface_level(double x, double y) const;
  // Distributed: readings of free_surface_level whose column of particles this rank shared with another rank
  // (it held some but not all of them); run.json reports the maximum over ranks (docs/contract.md).
  std::int64_t split_column_readings() const { return split_column_readings_; }
  // Rigid bodies (scene bodies of kind "rigid"; bodies/rigid_bodies.hpp): null when the scene has none.
  bodies::RigidBodies<D>* rigid_bodies() { return bodies_.get(); }
  const bodies::RigidBodies<D>* rigid_bodies() const { return bodies_.get(); }
  // Open boundaries: each particle's buffer zone (-1: not a buffer particle), or null when the scene has no
  // open boundaries. Buffer particles are kind 0 with prescribed kinematics: an implicit integrator holds
  // them (sim/open_boundaries.hpp). The pointer changes with every sort and growth: fetch it per loop.
  const std::int32_t* open_zones() const { return open_zone_ ? open_zone_->data.data() : nullptr; }
  // Whether the walls' state is extrapolated from the fluid (dummy Adami / mDBC: update_pressure does it).
  bool walls_extrapolated() const { return wall_v_ != nullptr; }
  // Advances the rigid bodies by dt from the loads at the current state (integrators call it after the
  // fluid's forces, before their drift's sort_and_bin places the bodies' particles); `drift` as in
  // RigidBodies::advance. No-op without rigid bodies. Every thread of a step region calls it.
  void advance_bodies(double dt, double drift);
  double cfl_dt() const;  // the CFL limit on the current state (for `info` and reports)
  // Shepard density re-initialisation (physics.shepard_reinit; Colagrossi & Landrini 2003):
  // rho_i = sum_j m_j W_ij / sum_j V_j W_ij for fluid particles, then p = EOS(rho). advance() calls it
  // every `every` steps after the integrator step (the grid must be valid for the current positions).
  void reinitialise_density();
  // Restores time/step counters (restart).
  void set_clock(double time, long step) { time_ = time; step_ = step; }
  const std::vector<Field<Vec<D>>*>& position_like() const { return position_like_; }

  // --- execution backend (execution.device; src/exec/, docs/gpu.md) --------------------------------
  // A device run keeps the particle state on the device between steps; the store is its host copy,
  // current only after sync_host(). Without a device these are no-ops.
  bool on_device() const { return device_ != nullptr; }
  exec::DeviceBackend<D>* device();
  // Copies a device run's state into the store (when the device is ahead) and bins it on the host, so
  // the store, grid and rates can be read as in a CPU run (frames, probes, checkpoints, diagnostics).
  void sync_host();
  // The store was written on the host (restart from a checkpoint): send it to the device.
  void host_state_changed();

  // --- distributed runs (src/parallel/; in one process these are identities) -----------------------
  // Integrators and output reduce through these instead of calling MPI: every rank gets the result.
  bool distributed() const { return domain_ != nullptr; }
  parallel::Communicator& comm() const { return *comm_; }
  parallel::Domain<D>* domain() { return domain_.get(); }
  double global_max(double v) const;
  double global_sum(double v) const;
  std::int64_t global_count() const;  // particles on all ranks
  // True on the one rank whose cells hold x (always in one process): point queries (probes) are
  // computed there, where every neighbour of x is an owned or ghost particle in the serial order.
  bool owns_point(const Vec<D>& x) const;
  // Rates for other parameters (the variational integrator's wall-free passes), with the halo
  // exchange of a distributed run in front of every pass.
  std::unique_ptr<physics::Rates<D>> make_rates(const physics::PhysicsParams<D>& p);
  // Owners' positions, velocities, densities and pressures of a view into the ghosts (for a pair loop
  // run outside the Rates passes); no-op in one process.
  void refresh_halo(const physics::ParticleView<D>& view);
  // The store now holds `n` particles that are rows [first_row, first_row + n) of a checkpoint (or of a
  // captured state) and no ghosts; the next sort_and_bin() partitions them anew. Restart and blow-up.
  // first_row < 0: the rows' order tags were restored with them (StateSnapshot) and are kept.
  void adopt_rows(std::size_t n, std::int64_t first_row);
  // --- particle removal (sim/health.*; a store-level operation a decomposition layer can call too) ----
  // Removes the particles at the given storage indices (strictly ascending) from every registered field
  // (ParticleStore::compact keeps the survivors' order and `id`), recounts the kinds and rebuilds the
  // neighbour grid for the survivors without moving walls; dummy walls re-extrapolate their pressure from
  // the fluid that is left. Integrator state lives in registered fields, so it stays consistent.
  // Distributed: owned indices; collective (every rank calls it when any rank removes, maybe with none).
  void remove_particles(std::span<const std::uint32_t> indices);
  // Resizes the store to n particles (restart from a checkpoint written after removals: the arrays are
  // copied in afterwards) and recounts the particle kinds from the `kind` field.
  void resize_particles(std::size_t n) { store_.resize(n); }
  // Counts of the whole run (owned particles summed over ranks: collective in a distributed run).
  void recount_kinds();
  // --- particle creation and the mass balance (ARCHITECTURE.md "open boundaries") ------------------
  // Appends copies of the particles src (every registered field, ParticleStore::append_copies) with new
  // ids from the run's one counter; returns the index of the first copy. The caller places them, then
  // recounts and rebins. One process only.
  std::size_t create_particles(std::span<const std::uint32_t> src);
  // The same on any number of ranks (every rank calls it, maybe with none): `order[k]` is copy k's place
  // among the `total` particles created this step on all ranks, in the order one process would create
  // them (ascending); its id is next_id() + order[k], and the counter advances by `total` on every rank,
  // so ids do not depend on the rank count. Distributed: the ghosts are dropped (Domain::append_owned) and
  // the caller rebins on every rank. `tag_base`: the places of particles already created this step before
  // these (a second batch: their order tags follow the first batch's, as one process appends them after it).
  std::size_t create_particles(std::span<const std::uint32_t> src, std::span<const std::int64_t> order,
                               std::int64_t total, std::int64_t tag_base = 0);
  std::int64_t next_id() const { return next_id_; }
  // Inlets and outlets (scene `open_boundaries`); null when the scene has none.
  OpenBoundaries<D>* open_boundaries() { return open_.get(); }
  const OpenBoundaries<D>* open_boundaries() const { return open_.get(); }
  FlowBalance& flow() { return flow_; }
  const FlowBalance& flow() const { return flow_; }
  // Mass of the fluid in the domain (kind 0, not in a buffer), summed in storage order and over ranks
  // (collective in a distributed run).
  double fluid_mass() const;
  // The id counter and the flows, for checkpoints and the last-good copy (restores bitwise).
  nlohmann::json save_flow_state() const;
  void restore_flow_state(const nlohmann::json& state);

 private:
  scene::Scene scene_;
  ParticleStore store_;
  ParticleFields<D> f_;
  physics::PhysicsParams<D> params_;
  physics::TaitEos eos_;
  NeighborGrid<D> grid_;
  std::unique_ptr<physics::Rates<D>> rates_;
  std::unique_ptr<Integrator<D>> integrator_;
  std::unique_ptr<exec::DeviceRun<D>> device_;  // execution.device != "cpu"
  std::unique_ptr<BoundaryMotion<D>> motion_;  // prescribed motion of boundary bodies (inactive if none)
  std::unique_ptr<bodies::RigidBodies<D>> bodies_;  // rigid bodies moved by the fluid (null if none)
  std::unique_ptr<OpenBoundaries<D>> open_;           // inlets and outlets (null if none)
  Field<std::int32_t>* open_zone_ = nullptr;          // their buffer tags (-1: not a buffer particle)
  std::int64_t next_id_ = 0;                          // the next created particle's id
  FlowBalance flow_;
  bool walls_move() const { return motion_->active() || bodies_ != nullptr; }
  std::vector<Field<Vec<D>>*> position_like_;
  Field<Vec<D>>* wall_v_ = nullptr;  // dummy walls / mDBC: velocity boundary particles show to viscosity
  Field<Real>* wall_distance_ = nullptr;    // mDBC: distance to the fluid-wall interface [m]
  Field<Vec<D>>* wall_acc_ = nullptr;       // extrapolated walls with prescribed motion: a_w [m/s^2]
  Field<Vec<D>>* xsph_ = nullptr;    // XSPH correction
  std::optional<physics::DampingZone<D>> damping_zone_;  // physics.damping_zone: absorbs waves (only when named)
  void apply_damping_zone(double dt);
  std::vector<std::uint32_t> perm_;
  std::vector<std::uint32_t> kept_;  // particle removal: indices of the survivors
  std::vector<Real> rho_scratch_;  // Shepard re-initialisation output (sized once)
  std::vector<Vec<D>> shift_scratch_;  // shifting displacements (sized once; consumed within the step)
  // free_surface_level: the fluid particles near the gauge's line (capacity kept: no allocation in the steps)
  struct ColumnParticle {
    std::uint64_t order;  // its place in the serial storage order: the row in one process, the order tag on ranks
    double x[D];          // its position (Real, exactly)
    double volume;        // m / rho
  };
  mutable std::vector<ColumnParticle> column_;
  mutable std::vector<std::byte> column_bytes_;  // distributed: every rank's column, gathered
  mutable std::int64_t split_column_readings_ = 0;
  std::size_t n_fluid_ = 0, n_boundary_ = 0;
  Real skin_ = 0;
  double time_ = 0, dt_ = 0;
  long step_ = 0;
  StepReport report_;
  bool one_region_ok_ = false;  // the step may run in one parallel region (below kOneRegionMax particles)
  std::shared_ptr<parallel::Communicator> comm_;  // one rank: a SerialCommunicator
  std::unique_ptr<parallel::Domain<D>> domain_;   // null in one process
};

}  // namespace varsph
