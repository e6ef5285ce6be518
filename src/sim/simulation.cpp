#include "sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <omp.h>

#include "core/errors.hpp"
#include "parallel/collective.hpp"
#include "parallel/communicator.hpp"
#include "parallel/domain.hpp"
#include "parallel/halo_rates.hpp"
#include "exec/device_run.hpp"
#include "physics/pair_loop.hpp"
#include "integrators/time_step_control.hpp"
#include "physics/corrections/corrections.hpp"
#include "sim/build_particles.hpp"
#include "sim/open_boundaries.hpp"
#include "sim/step_region.hpp"
#include "bodies/rigid_bodies.hpp"
#include "kernels/kernel_eval.hpp"

namespace varsph {
namespace {

template <int D>
physics::PhysicsParams<D> params_from(const scene::Scene& s) {
  physics::PhysicsParams<D> p;
  p.kernel = s.kernel;
  p.h = Real(s.h);
  p.kernel_l = Real(s.kernel_l);
  p.kernel_tabulated = s.kernel_tabulated;
  p.rho0 = Real(s.rho0);
  p.c0 = Real(s.c0);
  p.background_pressure = Real(s.background_pressure);
  for (int a = 0; a < D; ++a) p.gravity[a] = Real(s.gravity[a]);
  p.density = s.density == "summation" ? physics::DensityMode::Summation : physics::DensityMode::Continuity;
  p.artificial_viscosity = s.artificial_viscosity;
  p.riemann = s.riemann;
  p.riemann_eta = Real(s.riemann_eta);
  p.av_alpha = Real(s.av_alpha);
  p.av_beta = Real(s.av_beta);
  p.av_eps = Real(s.av_eps);
  p.boundary = s.boundary_model == "dynamic" ? physics::BoundaryModel::Dynamic : physics::BoundaryModel::Repulsive;
  p.wall_D = Real(s.wall_D);
  p.wall_r0 = Real(s.wall_r0);
  p.wall_n1 = s.wall_n1;
  p.wall_n2 = s.wall_n2;
  using physics::BoundaryModel;
  if (s.boundary_model == "dummy_adami") p.boundary = BoundaryModel::DummyAdami;
  if (s.boundary_model == "soft_repulsive") p.boundary = BoundaryModel::SoftRepulsive;
  if (s.boundary_model == "mdbc") p.boundary = BoundaryModel::Mdbc;
  p.mdbc_extrapolation = s.mdbc_extrapolation == "hydrostatic" ? physics::MdbcExtrapolation::Hydrostatic
                                                                : physics::MdbcExtrapolation::Gradient;
  p.wall_slip = s.wall_slip == "free_slip" ? physics::WallSlip::FreeSlip : physics::WallSlip::NoSlip;
  p.soft_wall_coef = Real(s.soft_wall_coef);
  p.dx = Real(s.spacing);
  p.laminar_viscosity = s.laminar_viscosity;
  p.nu = Real(s.nu);
  for (int a = 0; a < D && a < int(s.body_force.size()); ++a) p.body_force[a] = Real(s.body_force[a]);
  p.xsph_eps = Real(s.xsph_eps);
  p.damping = s.damping;
  p.damping_mu = Real(s.damping_mu);
  p.damping_until = Real(std::min(s.damping_until, 1e300));
  p.gravity_ramp = Real(s.gravity_ramp);
  p.diffusion = s.density_diffusion == "molteni"     ? physics::DensityDiffusion::Molteni
                : s.density_diffusion == "fourtakas" ? physics::DensityDiffusion::Fourtakas
                : s.density_diffusion == "antuono"   ? physics::DensityDiffusion::Antuono
                                                     : physics::DensityDiffusion::None;
  p.diffusion_delta = Real(s.diffusion_delta);
  p.tensile = s.tensile == "artificial_stress" ? physics::TensileFix::ArtificialStress : physics::TensileFix::None;
  p.as_eps = Real(s.as_eps);
  p.as_n = Real(s.as_n);
  p.shifting.enabled = s.shifting;
  p.shifting.A = Real(s.shift_A);
  p.shifting.global_speed = s.shift_velocity == "max";
  p.shifting.R = Real(s.shift_R);
  p.shifting.n = s.shift_n;
  p.shifting.free_surface_zero = s.shift_free_surface == "zero" || s.shift_free_surface == "tangential";
  p.shifting.tangential = s.shift_free_surface == "tangential";
  p.shifting.near_threshold = Real(s.shift_near_threshold);
  p.shifting.fs_threshold = Real(s.shift_fs_threshold);
  p.shifting.max_shift = Real(s.shift_max);
  return p;
}

}  // namespace

template <int D>
Simulation<D>::Simulation(const scene::Scene& scene, std::shared_ptr<parallel::Communicator> comm)
    : scene_(scene), f_(store_), params_(params_from<D>(scene)), eos_(Real(scene.rho0), Real(scene.c0), Real(scene.background_pressure)),
      comm_(comm ? std::move(comm) : std::make_shared<parallel::SerialCommunicator>()) {
  if (scene.dimension != D) throw std::logic_error("scene dimension does not match Simulation<D>");
  exec::check_device_scene(scene);  // a device this build or machine lacks, or a term not on it: exit 2 now
  rates_ = physics::make_rates<D>(params_);

  InitialParticles<D> init = build_particles<D>(scene, double(eos_.B));
  const std::size_t n = init.x.size();
  if (n >= std::size_t(UINT32_MAX)) throw InputError(scene.file.string() + ": too many particles");
  store_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    f_.x[i] = init.x[i];
    f_.v[i] = init.v[i];
    f_.a[i] = Vec<D>::Zero();
    f_.rho[i] = init.rho[i];
    f_.drho[i] = 0;
    f_.mass[i] = init.mass[i];
    f_.id[i] = std::int64_t(i);
    f_.kind[i] = init.kind[i];
    f_.normal[i] = init.normal[i];
    f_.body[i] = i < init.body.size() ? std::int32_t(init.body[i]) : -1;
  }
  if (params_.boundary == physics::BoundaryModel::DummyAdami ||
      params_.boundary == physics::BoundaryModel::SoftRepulsive || params_.boundary == physics::BoundaryModel::Mdbc)
  {
    wall_v_ = &store_.add<Vec<D>>("wall_velocity", {.exported = true});  // checkpointed: restarts stay bitwise
    // never written on fluid particles: zero, not what a resize of Eigen vectors leaves (uninitialised memory,
    // other bits in a distributed run; open boundaries' lattices copy a fluid particle's)
    for (auto& w : wall_v_->data) w.setZero();
  }
  if (params_.boundary == physics::BoundaryModel::Mdbc) {
    // distance of each boundary particle to the fluid-wall interface: its ghost node sits at twice that
    wall_distance_ = &store_.add<Real>("wall_distance", {.exported = false});
    for (std::size_t i = 0; i < n; ++i) wall_distance_->data[i] = init.wall_distance[i];
  }
  if (rates_->xsph_enabled())
    xsph_ = &store_.add<Vec<D>>("xsph_velocity", {.exported = true, .checkpointed = false});
  n_fluid_ = init.count(0);
  n_boundary_ = init.count(1);
  if (scene.damping_zone) {
    physics::DampingZone<D> z;
    Vec<D> to;
    for (int a = 0; a < D; ++a) {
      z.from[a] = Real(scene.damping_zone_from[std::size_t(a)]);
      to[a] = Real(scene.damping_zone_to[std::size_t(a)]);
    }
    z.length = (to - z.from).norm();
    z.normal = (to - z.from) / z.length;
    z.beta = Real(scene.damping_zone_beta);
    z.quadratic = scene.damping_zone_profile == "quadratic";
    damping_zone_ = z;
  }
  next_id_ = std::int64_t(n);
  if (!scene.open_boundaries.empty()) {  // buffer zones replace the fluid inside them (sim/open_boundaries.hpp)
    open_ = std::make_unique<OpenBoundaries<D>>(scene_, store_);  // the member: zones point into it
    open_zone_ = &store_.get<std::int32_t>("open_zone");
    open_->setup(*this, rates_->support());
  }
  // the fluid mass at t = 0 in build order, before a distributed run splits the particles: the same bits in
  // one process and on every rank
  flow_.mass0 = fluid_mass();

  {
    std::vector<MotionLaw<D>> laws;
    for (std::size_t b = 0; b < scene.bodies.size(); ++b)
      laws.push_back(parse_motion<D>(scene.bodies[b].motion, scene.file.string() + ": bodies." + std::to_string(b) + ".motion",
                                     &scene, b));
    motion_ = std::make_unique<BoundaryMotion<D>>(std::move(laws), store_);
    motion_->capture_reference(f_.x, f_.normal);
    if (scene.has_rigid_bodies()) bodies_ = std::make_unique<bodies::RigidBodies<D>>(scene, store_, f_, scene.rho0, scene.c0);
    // walls extrapolated from the fluid feel their own acceleration (Adami 2012 eq. 27, mDBC clone)
    if (walls_move() && wall_v_) {
      wall_acc_ = &store_.add<Vec<D>>("wall_acceleration", {.exported = false});
      // fixed walls are never written by the motion laws: zero, not what a resize of Eigen vectors leaves
      // (uninitialised memory; a distributed run read other bits than one process)
      for (auto& a : wall_acc_->data) a.setZero();
    }
    if (bodies_) bodies_->place(f_, store_.size(), wall_acc_);  // the bodies' initial velocities
  }
  integrator_ = make_integrator<D>(scene);
  // what several ranks cannot run yet: every rank decides alike and they agree (one message, exit 2)
  parallel::collectively(*comm_, [&] {
    if (comm_->size() > 1 && scene.device != "cpu")
      throw InputError(scene.file.string() + ": execution.device = \"" + scene.device + "\" is not available on "
                       "several MPI ranks yet (docs/parallel.md, Limits); run it in one process or on the CPU");
    if (comm_->size() > 1 && scene.output_static_boundary != "every_frame")  // one static file, not pieces
      throw InputError(scene.file.string() + ": key 'output.static_boundary': \"once\" is written by one process "
                       "only; run it in one process or set \"every_frame\"");
    if (comm_->size() > 1 && params_.boundary == physics::BoundaryModel::Mdbc)
      // a ghost node lies up to twice the wall thickness inside the fluid, beyond the halo of support + skin
      throw InputError(scene.file.string() + ": boundary.model = \"mdbc\" is not available on several MPI ranks yet "
                       "(docs/parallel.md, Limits); run it in one process or use \"dynamic\" or \"dummy_adami\" walls");
  });
  if (comm_->size() > 1) {
    // distributed: every rank built every particle (the same, deterministically); rank r keeps rows
    // [n r / P, n (r+1) / P) in id order, and the first sort_and_bin() moves them to their owners
    parallel::DomainOptions o;
    o.fluid_weight = scene.fluid_weight;
    o.boundary_weight = scene.boundary_weight;
    o.threshold = scene.rebalance_threshold;
    o.check_every = scene.rebalance_check_every;
    o.force_every = scene.rebalance_every;
    o.weights_by_cost = scene.weights_by_cost;
    domain_ = std::make_unique<parallel::Domain<D>>(comm_, o);
    domain_->attach(store_, {"position", "velocity", "density", "pressure", "mass", "kind", "id", "normal", "body",
                             "wall_velocity", "open_zone"});
    const std::size_t P = std::size_t(comm_->size()), r = std::size_t(comm_->rank());
    const std::size_t all = store_.size();  // built particles, with the open boundaries' lattices
    const std::size_t first = all * r / P, last = all * (r + 1) / P;
    for (const auto& fb : store_.fields()) {
      const std::size_t b = fb->bytes_per_particle();
      auto* raw = static_cast<std::byte*>(fb->raw());
      if (last > first) std::memmove(raw, raw + first * b, (last - first) * b);
    }
    store_.resize(last - first);
    domain_->adopt(store_, std::int64_t(first));
    rates_ = std::make_unique<parallel::HaloRates<D>>(std::move(rates_), *domain_);
  }
  // shifting moves particles by at most max_shift dx after the sort; a skin of twice that keeps the grid
  // valid for the shifted configuration (density update, next step's forces) without a second sort
  set_skin(rates_->shifting_enabled() ? Real(2) * params_.shifting.max_shift * params_.dx : Real(0));
  sort_and_bin();
  if (params_.density == physics::DensityMode::Summation) {
    const auto view = current_view();
    rates_->summation_density(grid_, view, f_.rho.data.data());
  }
  update_pressure();
  if (open_) open_->initial_values(*this);
  dt_ = scene.dt ? *scene.dt : cfl_dt();
  integrator_->initialize(*this);
  // one parallel region per step (core/team.hpp) for schemes written for it, in one process on the CPU
  one_region_ok_ = integrator_->one_region_step() && !domain_ && scene.device == "cpu" &&
                   dynamic_cast<const parallel::SerialCommunicator*>(comm_.get()) != nullptr &&
                   step_region_mode() == StepRegion::One;
  if (scene.device != "cpu") {  // initialised on the host, then stepped on the device
    device_ = std::make_unique<exec::DeviceRun<D>>(*this, std::move(integrator_));
    integrator_ = device_->take_integrator();
  }
}

template <int D>
Simulation<D>::~Simulation() = default;

template <int D>
exec::DeviceBackend<D>* Simulation<D>::device() {
  return device_ ? &device_->backend() : nullptr;
}

template <int D>
void Simulation<D>::sync_host() {
  if (!device_ || !device_->backend().device_ahead()) return;
  device_->backend().download();
  // the host grid for the downloaded positions: binned on the device by the same keys and a stable sort,
  // so the host sort keeps every particle where it is (permuted only if it does not)
  grid_.build(std::span<const Vec<D>>(f_.x.data), perm_);
  for (std::size_t k = 0; k < perm_.size(); ++k)
    if (perm_[k] != k) {
      store_.permute(perm_);
      device_->backend().upload();  // keep the two orders equal
      break;
    }
}

template <int D>
void Simulation<D>::host_state_changed() {
  if (device_) device_->backend().upload();
}

template <int D>
std::size_t Simulation<D>::ghosts() const {
  return domain_ ? domain_->ghosts() : 0;
}

template <int D>
double Simulation<D>::global_max(double v) const {
  return comm_->max(v);
}

template <int D>
double Simulation<D>::global_sum(double v) const {
  return comm_->sum(v);
}

template <int D>
std::int64_t Simulation<D>::global_count() const {
  return comm_->sum(std::int64_t(size()));
}

template <int D>
bool Simulation<D>::owns_point(const Vec<D>& x) const {
  return !domain_ || domain_->owns(x);
}

template <int D>
std::unique_ptr<physics::Rates<D>> Simulation<D>::make_rates(const physics::PhysicsParams<D>& p) {
  auto r = physics::make_rates<D>(p);
  if (domain_) return std::make_unique<parallel::HaloRates<D>>(std::move(r), *domain_);
  return r;
}

template <int D>
void Simulation<D>::refresh_halo(const physics::ParticleView<D>& view) {
  if (!domain_) return;
  std::vector<parallel::HaloArray> arrays;
  parallel::refresh_view(*domain_, view, parallel::kHaloPositions | parallel::kHaloVelocities | parallel::kHaloState,
                         arrays);
}

template <int D>
void Simulation<D>::adopt_rows(std::size_t n, std::int64_t first_row) {
  store_.resize(n);
  if (domain_ && first_row < 0) domain_->restore_owned(n);
  else if (domain_) domain_->adopt(store_, first_row);
}

template <int D>
std::size_t Simulation<D>::count(std::int32_t kind) const {
  return kind == 0 ? n_fluid_ : n_boundary_;
}

template <int D>
void Simulation<D>::recount_kinds() {
  n_fluid_ = n_boundary_ = 0;
  for (std::size_t i = 0; i < size(); ++i) (f_.kind[i] == 0 ? n_fluid_ : n_boundary_) += 1;
  if (domain_) {  // counts of the whole run on every rank (collective)
    std::int64_t c[2] = {std::int64_t(n_fluid_), std::int64_t(n_boundary_)};
    comm_->sum(std::span<std::int64_t>(c, 2));
    n_fluid_ = std::size_t(c[0]);
    n_boundary_ = std::size_t(c[1]);
  }
}

template <int D>
std::size_t Simulation<D>::create_particles(std::span<const std::uint32_t> src) {
  if (domain_) throw std::logic_error("Simulation::create_particles: give the creation order on several ranks");
  if (store_.size() + src.size() >= std::size_t(UINT32_MAX)) throw NumericalError("too many particles created");
  const std::size_t first = store_.append_copies(src);
  for (std::size_t k = 0; k < src.size(); ++k) f_.id[first + k] = next_id_++;
  return first;
}

template <int D>
std::size_t Simulation<D>::create_particles(std::span<const std::uint32_t> src, std::span<const std::int64_t> order,
                                            std::int64_t total, std::int64_t tag_base) {
  if (store_.size() + src.size() >= std::size_t(UINT32_MAX)) throw NumericalError("too many particles created");
  const std::size_t first = domain_ ? domain_->append_owned(store_, src, order, tag_base) : store_.append_copies(src);
  for (std::size_t k = 0; k < src.size(); ++k) f_.id[first + k] = next_id_ + order[k];
  next_id_ += total;
  return first;
}

template <int D>
double Simulation<D>::fluid_mass() const {
  double m = 0;  // serial, in storage order: the same bits on any thread count
  const std::int32_t* zone = open_zone_ ? open_zone_->data.data() : nullptr;
  for (std::size_t i = 0; i < size(); ++i)
    if (f_.kind[i] == 0 && (!zone || zone[i] < 0)) m += double(f_.mass[i]);
  return domain_ ? comm_->sum(m) : m;
}

template <int D>
nlohmann::json Simulation<D>::save_flow_state() const {
  return {{"next_id", next_id_},          {"created", flow_.created},
          {"removed_outlet", flow_.removed_outlet}, {"mass_in", flow_.mass_in},
          {"mass_out_outlet", flow_.mass_out_outlet}, {"mass_out_health", flow_.mass_out_health},
          {"mass0", flow_.mass0}};
}

template <int D>
void Simulation<D>::restore_flow_state(const nlohmann::json& j) {
  if (open_) open_->abandon_step();  // a step cut short by a blow-up left its buffer kinematics behind
  if (!j.is_object() || !j.contains("next_id")) {  // a checkpoint from before the flows were saved
    std::int64_t top = -1;
    for (std::size_t i = 0; i < size(); ++i) top = std::max(top, f_.id[i]);
    next_id_ = domain_ ? std::int64_t(comm_->max(double(top))) + 1 : top + 1;
    flow_ = FlowBalance{};
    flow_.mass0 = fluid_mass();  // the balance counts from the restart
    return;
  }
  next_id_ = j.at("next_id").get<std::int64_t>();
  flow_.created = j.at("created").get<long>();
  flow_.removed_outlet = j.at("removed_outlet").get<long>();
  flow_.mass_in = j.at("mass_in").get<double>();
  flow_.mass_out_outlet = j.at("mass_out_outlet").get<double>();
  flow_.mass_out_health = j.at("mass_out_health").get<double>();
  flow_.mass0 = j.at("mass0").get<double>();
}

template <int D>
void Simulation<D>::remove_particles(std::span<const std::uint32_t> indices) {
  double gone = 0;  // the fluid mass that leaves (the mass balance's health term)
  for (const std::uint32_t i : indices)
    if (i < size() && f_.kind[i] == 0 && (!open_zone_ || open_zone_->data[i] < 0)) gone += double(f_.mass[i]);
  flow_.mass_out_health += domain_ ? comm_->sum(gone) : gone;  // collective like the removal itself
  if (indices.empty() && !domain_) return;
  const std::size_t n = size();  // owned particles (ghosts are rebuilt, never removed)
  kept_.clear();
  kept_.reserve(n - indices.size());
  std::size_t r = 0;
  for (std::uint32_t i = 0; i < std::uint32_t(n); ++i) {
    if (r < indices.size() && indices[r] == i) {
      ++r;
      continue;
    }
    kept_.push_back(i);
  }
  if (r != indices.size()) throw std::logic_error("Simulation::remove_particles: indices not ascending or out of range");
  if (domain_) {  // collective: the survivors keep their order tags, rebin() rebuilds the ghosts and grid
    domain_->compact_owned(store_, kept_);
    recount_kinds();
    domain_->rebin(store_, grid_, position_like_);
    if (wall_v_) update_pressure();
    return;
  }
  store_.compact(kept_);
  recount_kinds();
  // the survivors keep their cell order, so this stable sort only rebuilds the blocks and ranges
  grid_.build(std::span<const Vec<D>>(f_.x.data), perm_);
  store_.permute(perm_);
  if (wall_v_) update_pressure();  // dummy walls: extrapolated from the fluid that is left
}

template <int D>
void Simulation<D>::set_skin(Real skin) {
  skin_ = skin;
  typename NeighborGrid<D>::Options o;
  for (int a = 0; a < D; ++a) {
    o.min[a] = Real(scene_.domain_min[a]);
    o.max[a] = Real(scene_.domain_max[a]);
    o.periodic[a] = scene_.periodic[a];
  }
  o.hashed = scene_.neighbor_search == "hash";
  o.cell_size = rates_->support() + skin;
  try {
    grid_.configure(o);
  } catch (const std::invalid_argument& e) {
    throw InputError(scene_.file.string() + ": domain: " + e.what());
  }
}

template <int D>
void Simulation<D>::move_boundaries(double t) {
  motion_->apply(t, f_.x, f_.v, f_.normal, f_.body, wall_acc_);
  if (bodies_) bodies_->place(f_, size(), wall_acc_);
}

template <int D>
void Simulation<D>::advance_bodies(double dt, double drift) {
  if (bodies_) bodies_->advance(*this, dt, drift);
}

template <int D>
void Simulation<D>::sort_and_bin() {
  // moving walls take their place in the new configuration (time t + dt) before binning
  if (motion_ && walls_move()) team_single([&] { move_boundaries(time_ + dt_); });
  // buffer particles likewise: x0 + dt v0 (Tafuni 2018 sec. 3.1), not the integrator's drift
  if (open_) open_->place_buffers(*this);
  rebin();
}

template <int D>
void Simulation<D>::rebin() {
  if (domain_) {  // migrate, order as one process would, ghosts, grid (parallel/domain.hpp)
    team_single([&] { domain_->rebin(store_, grid_, position_like_); });  // never in a step region today
    return;
  }
  auto& x = f_.x.data;
  bool any_periodic = false;
  for (int a = 0; a < D; ++a) any_periodic |= scene_.periodic[a];
  if (any_periodic) {
    for_each_particle(x.size(), [&](std::size_t i) {  // each particle its own slots
      const Vec<D> s = grid_.wrap_shift(x[i]);
      if (s.squaredNorm() > 0) {
        x[i] += s;
        for (auto* f : position_like_) f->data[i] += s;
      }
    });
  }
  grid_.build(std::span<const Vec<D>>(x), perm_);
  store_.permute(perm_);
}

template <int D>
physics::ParticleView<D> Simulation<D>::current_view() const {
  physics::ParticleView<D> v{f_.x.data, f_.v.data, f_.rho.data, f_.p.data, f_.mass.data, f_.kind.data};
  if (wall_v_) {
    v.wall_v = wall_v_->data;
    v.normal = f_.normal.data;
  }
  return v;
}

template <int D>
Vec<D>* Simulation<D>::compute_xsph() {
  if (!xsph_) return nullptr;
  rates_->xsph(grid_, current_view(), xsph_->data.data());
  return xsph_->data.data();
}

template <int D>
void Simulation<D>::apply_shifting() {
  if (!rates_->shifting_enabled()) return;
  team_single([&] { shift_scratch_.resize(store_.size()); });
  Vec<D>* dr = shift_scratch_.data();
  rates_->shifting(grid_, current_view(), Real(dt_), dr);
  Vec<D>* x = f_.x.data.data();
  const std::int32_t* kind = f_.kind.data.data();
  for_each_particle(size(), [&](std::size_t i) {
    if (kind[i] == 0) x[i] += dr[i];  // positions only: velocities, masses, momentum unchanged
  });
}

template <int D>
void Simulation<D>::update_pressure() {
  Real* p = f_.p.data.data();
  const Real* rho = f_.rho.data.data();
  const auto eos = eos_;
  for_each_particle(store_.size(), [&](std::size_t i) { p[i] = eos.pressure(rho[i]); });
  // dummy walls (Adami 2012): boundary pressure, density and viscous velocity from the fluid
  if (wall_v_) rates_->update_walls(grid_, current_view(), wall_geometry(), p, f_.rho.data.data(), wall_v_->data.data());
}

template <int D>
physics::WallGeometry<D> Simulation<D>::wall_geometry() const {
  physics::WallGeometry<D> g;
  g.normal = f_.normal.data.data();
  if (wall_distance_) g.distance = wall_distance_->data.data();
  if (wall_acc_) g.acceleration = wall_acc_->data.data();
  return g;
}

template <int D>
void Simulation<D>::update_density_after_move(Real dt) {
  const auto view = current_view();
  if (params_.density == physics::DensityMode::Summation) {
    rates_->summation_density(grid_, view, f_.rho.data.data());
  } else {
    Real* drho = f_.drho.data.data();
    rates_->density_rate(grid_, view, drho);
    Real* rho = f_.rho.data.data();
    const std::int32_t* kind = f_.kind.data.data();
    const bool walls = params_.boundary == physics::BoundaryModel::Dynamic;
    for_each_particle(size(), [&](std::size_t i) {
      if (kind[i] == 0 || walls) rho[i] += dt * drho[i];
    });
  }
  update_pressure();
}

template <int D>
double Simulation<D>::cfl_dt() const {
  // acoustic, force and viscous limits, each with its coefficient (integrators/time_step_control.hpp)
  return cfl_limits(*this).dt();
}

template <int D>
double Simulation<D>::choose_dt() const {
  return scene_.dt ? *scene_.dt : cfl_dt();
}

template <int D>
bool Simulation<D>::steps_in_one_region() const {
  return one_region_ok_ && size() + ghosts() < kOneRegionMax && omp_get_max_threads() > 1;
}

template <int D>
const StepReport& Simulation<D>::advance() {
  return advance(std::function<void()>());
}

template <int D>
const StepReport& Simulation<D>::advance(const std::function<void()>& after_step) {
  // active absorption: the paddle's correction for this step from the elevation at its gauge at t_k
  if (motion_->absorbing())
    motion_->absorb(time_, [&](double x, double y) { return free_surface_level(x, y); });
  if (walls_move()) move_boundaries(time_);  // walls at t_k for the forces of this step
  if (open_) open_->before_step(*this);  // buffer particles' positions and velocities at t_k
  rates_->set_time(time_);  // gravity ramp, damping window
  if (domain_) domain_->step_begin();
  // Shepard re-initialisation changes the densities after the step: the check then runs after it
  const bool reinit = scene_.shepard_reinit_every > 0 && (step_ + 1) % scene_.shepard_reinit_every == 0;
  bool checked = false;
  if (steps_in_one_region()) {
    run_team([&] {  // one fork/join for the whole step (core/team.hpp)
      const StepReport r = integrator_->step(*this);
      if (damping_zone_) apply_damping_zone(dt_);  // after the step, as DualSPHysics applies it after the corrector
      team_single([&] { report_ = r; });
      if (after_step && !reinit && !open_) after_step();
    });
    checked = !reinit && !open_;
  } else {
    report_ = integrator_->step(*this);
    if (damping_zone_) apply_damping_zone(dt_);
  }
  ++step_;
  if (domain_) domain_->step_end(step_);  // load balance: may schedule a repartition for the next sort
  // fixed dt: t = t0 + k dt exactly as two runs with the same dt compute it (frames match by time)
  time_ += dt_;
  if (open_) open_->after_step(*this);  // buffers imposed, particles created and removed, grid rebuilt
  if (scene_.shepard_reinit_every > 0 && step_ % scene_.shepard_reinit_every == 0) reinitialise_density();
  if (after_step && !checked) after_step();
  return report_;
}

template <int D>
double Simulation<D>::free_surface_level(double x, double y) const {
  const kernels::AnyKernel<D> W(scene_.kernel, scene_.h, scene_.kernel_l);
  const double rc = double(W.support());
  // the bed: the lowest fluid box's floor (as the wavemaker's depth is measured)
  double bed = 1e300;
  for (const auto& b : scene_.bodies)
    if (b.kind == "fluid" && b.shape == "box" && b.min.size() == std::size_t(D)) bed = std::min(bed, b.min[D - 1]);
  if (bed == 1e300) bed = scene_.domain_min[D - 1];
  // fluid particles near the line (horizontal distance below the support) in storage order, with their order key
  const auto& f = f_;
  column_.clear();
  for (std::size_t j = 0; j < size(); ++j) {
    if (f.kind[j] != 0) continue;
    double d2 = (double(f.x[j][0]) - x) * (double(f.x[j][0]) - x);
    if (D == 3) d2 += (double(f.x[j][1]) - y) * (double(f.x[j][1]) - y);
    if (d2 < rc * rc) {
      ColumnParticle c;
      c.order = domain_ ? std::uint64_t(domain_->order_tag(j)) : std::uint64_t(j);
      for (int a = 0; a < D; ++a) c.x[a] = double(f.x[j][a]);
      c.volume = double(f.mass[j]) / double(f.rho[j]);
      column_.push_back(c);
    }
  }
  if (domain_) {
    // several ranks share the column: every rank gathers every rank's part and sums in the order tags' order, the
    // serial storage order (parallel/domain.hpp), so that the indicator's sums have one process's bits on every rank
    const auto* b = reinterpret_cast<const std::byte*>(column_.data());
    const std::size_t mine = column_.size();
    comm_->allgatherv(std::span<const std::byte>(b, mine * sizeof(ColumnParticle)), column_bytes_);
    if (mine > 0 && mine * sizeof(ColumnParticle) < column_bytes_.size()) ++split_column_readings_;
    column_.resize(column_bytes_.size() / sizeof(ColumnParticle));
    if (!column_bytes_.empty()) std::memcpy(column_.data(), column_bytes_.data(), column_bytes_.size());
    std::sort(column_.begin(), column_.end(),
              [](const ColumnParticle& a, const ColumnParticle& c) { return a.order < c.order; });
  }
  double top = -1e300;  // the highest of them
  for (const auto& c : column_) top = std::max(top, c.x[D - 1]);
  if (column_.empty()) return bed;  // dry
  const double step = scene_.spacing / 4;
  auto phi_at = [&](long k) {
    Vec<D> p;
    p[0] = Real(x);
    if (D == 3) p[1] = Real(y);
    p[D - 1] = Real(bed + double(k) * step);
    double phi = 0;
    for (const auto& c : column_) {
      Vec<D> xj;
      for (int a = 0; a < D; ++a) xj[a] = Real(c.x[a]);
      const Real r = (p - xj).norm();
      if (r < Real(rc)) phi += c.volume * double(W(r).w);
    }
    return phi;
  };
  // above top + rc the indicator is 0: the highest crossing lies below; search down from there to a level where
  // the column is full (phi >= 1/2), normally within 2 rc (then the whole column: a drop above the water)
  const long k_hi = long(std::ceil((top + rc - bed) / step));
  long k_lo = std::max(0L, long(std::floor((top - 2 * rc - bed) / step)));
  if (k_lo > 0 && phi_at(k_lo) < 0.5) k_lo = 0;
  double level = bed, prev_phi = 0;
  for (long k = k_lo; k <= k_hi; ++k) {
    const double phi = phi_at(k);
    if (k > k_lo && prev_phi >= 0.5 && phi < 0.5)
      level = bed + double(k - 1) * step + (prev_phi - 0.5) / (prev_phi - phi) * step;  // linear interpolation
    prev_phi = phi;
  }
  return level;
}

template <int D>
void Simulation<D>::apply_damping_zone(double dt) {
  const physics::DampingZone<D> z = *damping_zone_;
  const Real h = Real(dt);
  Vec<D>* v = f_.v.data.data();
  const Vec<D>* x = f_.x.data.data();
  const std::int32_t* kind = f_.kind.data.data();
  for_each_particle(size(), [&](std::size_t i) {  // owned particles; each its own slot
    if (kind[i] == 0) v[i] *= z.factor(x[i], h);
  });
}

template <int D>
void Simulation<D>::reinitialise_density() {
  rho_scratch_.resize(store_.size());
  refresh_halo(current_view());  // Shepard sums read the neighbours' positions, masses and densities
  const auto o = physics::corrections::Options::of(params_);
  physics::corrections::shepard_density<D>(grid_, current_view(), o, rho_scratch_);
  Real* rho = f_.rho.data.data();
  const std::int32_t* kind = f_.kind.data.data();
  const Real* out = rho_scratch_.data();
  // fluid particles only: wall densities (dynamic model) keep their own continuity evolution
  for_each_particle(size(), [&](std::size_t i) {
    if (kind[i] == 0) rho[i] = out[i];
  });
  update_pressure();
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace varsph
