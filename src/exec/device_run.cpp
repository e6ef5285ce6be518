#include "exec/device_run.hpp"

#include <algorithm>

#include "core/errors.hpp"
#include "integrators/time_step_control.hpp"
#include "integrators/variational.hpp"
#include "kernels/tabulated.hpp"
#include "sim/diagnostics.hpp"
#include "sim/simulation.hpp"

namespace varsph::exec {
namespace {

// The integrators the device runs (docs/gpu.md "What runs on the device").
const char* const kDeviceIntegrators = "\"verlet\", \"verlet_dsph\", \"symplectic_euler\", \"variational\"";

[[noreturn]] void refuse(const scene::Scene& s, const std::string& key, const std::string& what) {
  throw InputError(s.file.string() + ": key '" + key + "': " + what + " is not available on the device yet " +
                   "(execution.device = \"" + s.device + "\"; docs/gpu.md lists what runs there); run this scene "
                   "with execution.device = \"cpu\"");
}

// The host side of a device run: what the backend asks of the simulation between its loops.
template <int D>
class SimulationHostSide final : public HostSide<D> {
 public:
  explicit SimulationHostSide(Simulation<D>& sim) : sim_(sim) {}
  GridView<D> set_skin(Real skin) override {
    sim_.set_skin(skin);
    return grid_view_of(sim_.grid());
  }
  Real skin() const override { return sim_.skin(); }
  Vec<D> body_acceleration() const override { return sim_.rates().body_acceleration(); }
  bool fixed_dt() const override { return sim_.scene().dt.has_value(); }
  double choose_dt(double v_max, double a_max) const override {
    return sim_.scene().dt ? *sim_.scene().dt : cfl_limits(sim_, v_max, a_max).dt();
  }
  double dt() const override { return sim_.dt(); }
  void set_dt(double dt) override { sim_.set_dt(dt); }
  double time() const override { return sim_.time(); }
  long step() const override { return sim_.step(); }

 private:
  Simulation<D>& sim_;
};

// The integrator a device run steps with: the host integrator's name, kind and checkpoint state (the same
// keys, so checkpoints move between CPU and GPU runs), the device's loops.
template <int D>
class DeviceIntegrator final : public Integrator<D> {
 public:
  DeviceIntegrator(std::unique_ptr<Integrator<D>> host, DeviceBackend<D>& backend, DeviceIntegratorKind kind)
      : host_(std::move(host)), backend_(backend), kind_(kind) {
    restore_state(host_->save_state());
  }
  const char* name() const override { return host_->name(); }
  bool implicit() const override { return host_->implicit(); }
  double dt_bound() const override { return kind_ == DeviceIntegratorKind::Variational ? state_.last_bound : 0.0; }
  void initialize(Simulation<D>&) override {}  // done on the host before the upload
  StepReport step(Simulation<D>&) override {
    const DeviceStepReport r = backend_.step(state_);
    return {r.iterations, r.residual, r.contraction, r.dt_bound};
  }
  nlohmann::json save_state() const override {
    if (kind_ == DeviceIntegratorKind::VerletDsph) return {{"steps_since_euler", state_.steps_since_euler}};
    if (kind_ == DeviceIntegratorKind::Variational)
      return {{"dt_prev", state_.dt_prev},
              {"halvings", state_.halvings},
              {"steps_since_change", state_.steps_since_change},
              {"dt_bound", state_.last_bound}};
    return nlohmann::json::object();
  }
  void restore_state(const nlohmann::json& j) override {
    if (j.contains("steps_since_euler")) state_.steps_since_euler = j.at("steps_since_euler").get<long>();
    if (j.contains("dt_prev")) state_.dt_prev = j.at("dt_prev").get<double>();
    if (j.contains("halvings")) state_.halvings = j.at("halvings").get<int>();
    if (j.contains("steps_since_change")) state_.steps_since_change = j.at("steps_since_change").get<long>();
    if (j.contains("dt_bound")) state_.last_bound = j.at("dt_bound").get<double>();
  }

 private:
  std::unique_ptr<Integrator<D>> host_;
  DeviceBackend<D>& backend_;
  DeviceIntegratorKind kind_;
  DeviceStepState state_;
};

DeviceIntegratorKind integrator_kind(const std::string& name) {
  if (name == "verlet_dsph") return DeviceIntegratorKind::VerletDsph;
  if (name == "symplectic_euler") return DeviceIntegratorKind::SymplecticEuler;
  if (name == "variational") return DeviceIntegratorKind::Variational;
  return DeviceIntegratorKind::Verlet;
}

template <int D>
DeviceSetup<D> setup_of(Simulation<D>& sim) {
  const auto& sc = sim.scene();
  DeviceSetup<D> s;
  s.params = sim.params();
  s.eos = sim.eos();
  const kernels::Tabulated<D> table(s.params.kernel, s.params.h, s.params.kernel_l);  // RatesImpl's table
  s.table_w = table.w_values();
  s.table_f = table.f_values();
  const auto tv = table.view(nullptr, nullptr);
  s.table_scale = tv.scale_;
  s.table_intervals = tv.intervals_;
  s.support = table.support();
  s.grid = grid_view_of(sim.grid());
  // dummy walls read normals: free-slip extrapolation, and artificial viscosity's free-slip mirror
  const bool extrapolated_walls = s.params.boundary == physics::BoundaryModel::DummyAdami;
  for (const auto& f : sim.store().fields()) {
    s.fields.push_back(f.get());
    // read by no device loop: reordered on the host at download through the particles' origin index
    const bool host_only = f->name() == "id" || f->name() == "body" || (f->name() == "normal" && !extrapolated_walls);
    s.host_only.push_back(host_only);
  }
  for (const auto* f : sim.position_like()) s.position_like.push_back(f->name());
  s.n = sim.size();
  s.integrator = integrator_kind(sc.integrator);
  s.euler_every = sc.euler_every;
  s.alpha = sc.alpha;
  s.spacing = sc.spacing;
  s.fp_tolerance = sc.fp_absolute_tolerance ? *sc.fp_absolute_tolerance : sc.fp_tolerance * sc.spacing;
  s.fp_max_iterations = sc.fp_max_iterations;
  s.halve_on_failure = sc.fp_on_failure == "halve_dt";
  if (s.integrator == DeviceIntegratorKind::Variational) {
    // the host integrator's case split (VariationalIntegrator's constructor and initialize())
    const bool summation = sc.density == "summation";
    const bool viscous = sc.artificial_viscosity && (sc.av_alpha > 0 || sc.av_beta > 0);
    s.variational_explicit = sc.alpha == 1.0 || (sc.alpha == 0.0 && summation && !viscous);
    s.variational_wall = !s.variational_explicit && s.params.boundary == physics::BoundaryModel::Repulsive &&
                         s.params.wall_D > 0;
  }
  s.max_density_error = sc.health.max_density_error;
  s.max_speed = sc.health.max_mach * sc.c0;
  for (int a = 0; a < D; ++a) {
    s.domain_min[a] = sc.domain_min[std::size_t(a)];
    s.domain_max[a] = sc.domain_max[std::size_t(a)];
  }
  return s;
}

}  // namespace

template <int D>
GridView<D> grid_view_of(const NeighborGrid<D>& grid) {
  GridView<D> g{};
  const auto& o = grid.options();
  g.n_cells = 1;
  for (int a = 0; a < D; ++a) {
    g.min[a] = o.min[a];
    g.max[a] = o.max[a];
    g.len[a] = o.max[a] - o.min[a];
    g.cell[a] = grid.cell_size(a);
    g.dims[a] = grid.cells_per_axis()[std::size_t(a)];
    g.periodic[a] = o.periodic[a];
    g.n_cells *= std::uint64_t(g.dims[a]);
  }
  g.m = std::max(1, o.subdivision);
  return g;
}

void check_device_scene(const scene::Scene& s) {
  if (s.device == "cpu") return;
  if (s.device == "cuda") {
    if (!cuda_compiled())
      throw InputError(s.file.string() + ": key 'execution.device': \"cuda\" needs a build with the CUDA backend; "
                       "this varsph was built without it (no nvcc found at configure time, or -DVARSPH_CUDA=OFF; "
                       "docs/gpu.md). Use execution.device = \"cpu\"");
    std::string why;
    if (!cuda_device_present(&why))
      throw InputError(s.file.string() + ": key 'execution.device': \"cuda\" was asked for, but no CUDA device is "
                       "present (" + why + "). Use execution.device = \"cpu\"");
  }
  const std::string& in = s.integrator;
  if (in != "verlet" && in != "verlet_dsph" && in != "symplectic_euler" && in != "variational")
    refuse(s, "integrator.type", "the integrator \"" + in + "\" (on the device: " + kDeviceIntegrators + ")");
  if (!s.kernel_tabulated) refuse(s, "kernel.tabulated", "the exact (untabulated) kernel evaluation");
  if (s.neighbor_search != "cell") refuse(s, "domain.neighbor_search", "the hash grid (\"" + s.neighbor_search + "\")");
  if (s.boundary_model == "soft_repulsive") refuse(s, "boundary.model", "the soft repulsive wall (Chalk 2020)");
  if (s.boundary_model == "mdbc") refuse(s, "boundary.model", "the mDBC wall (English 2022)");
  if (s.xsph_eps > 0) refuse(s, "physics.xsph", "XSPH");
  if (s.damping) refuse(s, "physics.damping", "viscous damping");
  if (s.damping_zone) refuse(s, "physics.damping_zone", "the damping zone (wave absorption)");
  if (s.tensile != "none") refuse(s, "physics.tensile_instability", "artificial stress");
  if (s.shifting) refuse(s, "physics.shifting", "particle shifting");
  if (s.shepard_reinit_every > 0) refuse(s, "physics.shepard_reinit", "Shepard density re-initialisation");
  for (std::size_t b = 0; b < s.bodies.size(); ++b)
    if (!s.bodies[b].motion.is_null()) {
      const auto& m = s.bodies[b].motion;
      const std::string type = m.is_object() && m.contains("type") && m["type"].is_string() ? m["type"].get<std::string>() : "";
      refuse(s, "bodies." + std::to_string(b) + ".motion",
             type == "piston" || type == "flap" ? "the " + type + " wavemaker (prescribed boundary motion)"
                                                : "prescribed boundary motion");
    }
  if (!s.open_boundaries.empty()) refuse(s, "open_boundaries", "open boundaries (inlets and outlets)");
  for (std::size_t b = 0; b < s.bodies.size(); ++b)
    if (s.bodies[b].kind == "rigid") refuse(s, "bodies." + std::to_string(b) + ".kind", "rigid bodies (\"rigid\")");
}

template <int D>
DeviceRun<D>::DeviceRun(Simulation<D>& sim, std::unique_ptr<Integrator<D>> host_integrator) {
  host_ = std::make_unique<SimulationHostSide<D>>(sim);
  const DeviceSetup<D> setup = setup_of(sim);
  backend_ = sim.scene().device == "cuda" ? make_cuda_backend<D>(setup, *host_) : make_emulation_backend<D>(setup, *host_);
  integrator_ = std::make_unique<DeviceIntegrator<D>>(std::move(host_integrator), *backend_, setup.integrator);
  backend_->upload();
}

template <int D>
DeviceRun<D>::~DeviceRun() = default;

template <int D>
std::unique_ptr<Integrator<D>> DeviceRun<D>::take_integrator() {
  return std::move(integrator_);
}

template <int D>
std::string check_device_health(Simulation<D>& sim) {
  const std::int64_t bad = sim.device()->first_unhealthy();
  if (bad < 0) return {};
  sim.sync_host();  // the host check names the same (lowest-index) particle with the host's message
  std::string msg = check_health(sim);
  if (msg.empty()) msg = "particle index " + std::to_string(bad) + " failed the device health check";
  // bench_gpu stops at the first violation; `varsph run` applies the health rules instead (Runner)
  return "device health check: " + msg;
}

template GridView<2> grid_view_of<2>(const NeighborGrid<2>&);
template GridView<3> grid_view_of<3>(const NeighborGrid<3>&);
template class DeviceRun<2>;
template class DeviceRun<3>;
template std::string check_device_health<2>(Simulation<2>&);
template std::string check_device_health<3>(Simulation<3>&);

}  // namespace varsph::exec
