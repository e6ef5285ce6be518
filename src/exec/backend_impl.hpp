#pragma once
// The device backend, written once over a launch policy (docs/gpu.md): Launch = the CUDA launch
// (src/exec/cuda/, nvcc) or the host launch that emulates it (host_launch.hpp). It owns the device mirror
// of the particle store (one device array per registered field, reordered with it), the cell grid, the
// compiled passes of the scene's terms and the loops of the integrators `verlet`, `symplectic_euler`,
// `verlet_dsph` and `variational` (alpha, fixed point, contraction watch, dt halving). Included only by
// the two translation units that instantiate it (host_emulation.cpp, cuda/backend_cuda.cu).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <span>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/errors.hpp"
#include "exec/device_backend.hpp"
#include "exec/loop_bodies.hpp"
#include "exec/pass_makers.hpp"
#include "exec/step_bodies.hpp"

namespace varsph::exec {

template <int D, class Launch>
class Backend final : public DeviceBackend<D> {
  using View = physics::ParticleView<D>;
  using BM = physics::BoundaryModel;

 public:
  Backend(const DeviceSetup<D>& setup, HostSide<D>& host)
      : s_(setup), host_(host), n_(setup.n), capacity_(setup.n) {
    g_ = s_.grid;
    rc2_ = s_.support * s_.support;
    const auto& p = s_.params;
    wall_ = physics::RepulsiveWall(p.wall_D, p.wall_r0, p.wall_n1, p.wall_n2);
    no_wall_ = physics::RepulsiveWall(Real(0), p.wall_r0, p.wall_n1, p.wall_n2);  // without_wall() of variational.cpp
    soft_ = physics::SoftRepulsiveWall(p.soft_wall_coef, p.c0, p.dx, p.h);
    av_ = physics::ArtificialViscosity(p.av_alpha, p.av_beta, p.c0, p.h, p.av_eps);
    lam_ = physics::LaminarViscosity(p.nu, p.h);
    riemann_ = physics::RiemannDissipation(p.rho0, p.c0, p.riemann_eta);
    try {
      allocate();
    } catch (...) {
      free_all();
      throw;
    }
    pick_passes();
    // page-locked host copies of what asynchronous downloads write (frames, checkpoints)
    origin_snap_host_.resize(n_);
    launch_.pin(origin_snap_host_.data(), n_ * sizeof(std::uint32_t));
    for (auto& f : f_)
      if (f.dev && f.checkpointed) launch_.pin(f.host->raw(), f.elem * n_);
  }
  ~Backend() override {
    launch_.wait_host_async();
    launch_.unpin(origin_snap_host_.data());
    for (auto& f : f_)
      if (f.dev && f.checkpointed) launch_.unpin(f.host->raw());
    free_all();
  }

  const char* name() const override { return Launch::name(); }

  void upload() override {
    // the store shrinks when the health rules remove particles (Runner): the device arrays, allocated for
    // the initial count, keep their capacity and the backend works on the first n_
    const std::size_t n = s_.fields.front()->size();
    if (n > capacity_) throw std::logic_error("device backend: the store grew past the device arrays");
    n_ = n;
    for (auto& f : f_)
      if (f.dev) launch_.to_device(f.dev, f.host->raw(), f.elem * n_);
    launch_.for_each(n_, IotaBody{origin_});
    snapshot_valid_ = false;
    sort_and_bin();
    device_ahead_ = true;  // the device sort is the identity on a binned store, but the host copy is not used
  }

  void download() override {
    if (!device_ahead_) return;
    for (auto& f : f_)
      if (f.dev) launch_.to_host(f.host->raw(), f.dev, f.elem * n_);
    if (any_host_only_) {
      // host-only fields follow the device's reordering since the last upload: new[k] = old[origin[k]]
      origin_host_.resize(n_);
      launch_.to_host(origin_host_.data(), origin_, n_ * sizeof(std::uint32_t));
      permute_host_only(origin_host_);
      // the last-good copy's order, re-expressed against the new host order: snap' = origin^-1 o snap
      if (snapshot_valid_) {
        std::uint32_t* inv = work_u32(0);
        launch_.for_each(n_, InvertBody{origin_, inv});
        launch_.for_each(n_, ComposeBody{inv, origin_snap_, work_u32(1)});
        launch_.copy(origin_snap_, work_u32(1), n_ * sizeof(std::uint32_t));
      }
      launch_.for_each(n_, IotaBody{origin_});
    }
    launch_.synchronize();
    device_ahead_ = false;
  }
  bool device_ahead() const override { return device_ahead_; }

  DeviceStepReport step(DeviceStepState& st) override {
    device_ahead_ = true;
    switch (s_.integrator) {
      case DeviceIntegratorKind::Verlet:
      case DeviceIntegratorKind::SymplecticEuler: kick_drift_step(); return {};
      case DeviceIntegratorKind::VerletDsph: verlet_dsph_step(st); return {};
      case DeviceIntegratorKind::Variational: return variational_step(st);
    }
    return {};
  }

  std::int64_t first_unhealthy() override {
    const double rho0 = double(s_.params.rho0);
    HealthBody<D> b{vec(ix_), vec(iv_), real(irho_), kind(), rho0 * (1.0 - s_.max_density_error),
                    rho0 * (1.0 + s_.max_density_error), s_.max_speed * s_.max_speed, {}, {}, {}};
    for (int a = 0; a < D; ++a) {
      b.lo[a] = s_.domain_min[a];
      b.hi[a] = s_.domain_max[a];
      b.periodic[a] = g_.periodic[a];
    }
    const std::uint64_t i = launch_.template reduce<MinIndexOp>(n_, b);
    return i == MinIndexOp::identity() ? -1 : std::int64_t(i);
  }

  void snapshot_capture() override {
    for (auto& f : f_)
      if (f.dev && f.checkpointed) launch_.copy(f.snap, f.dev, f.elem * n_);
    launch_.copy(origin_snap_, origin_, n_ * sizeof(std::uint32_t));
    snapshot_valid_ = true;
  }
  void snapshot_restore() override {
    if (!snapshot_valid_) return;
    for (auto& f : f_)
      if (f.dev && f.checkpointed) launch_.copy(f.dev, f.snap, f.elem * n_);
    launch_.copy(origin_, origin_snap_, n_ * sizeof(std::uint32_t));
    sort_and_bin();  // the saved state was binned: the identity order, and the grid arrays for it
    device_ahead_ = true;
  }
  // everything allocated on the device (cell arrays, kernel table and sort scratch included) but the
  // last-good copy
  void begin_snapshot_download() override {
    if (!snapshot_valid_) throw std::logic_error("begin_snapshot_download without a snapshot");
    for (auto& f : f_)
      if (f.dev && f.checkpointed) launch_.to_host_async(f.host->raw(), f.snap, f.elem * n_);
    if (any_host_only_) launch_.to_host_async(origin_snap_host_.data(), origin_snap_, n_ * sizeof(std::uint32_t));
    download_pending_ = true;
  }
  void finish_snapshot_download() override {
    if (!download_pending_) return;
    launch_.wait_host_async();
    download_pending_ = false;
    if (!any_host_only_) return;
    // the host-only fields in the snapshot's order; the device's origins re-expressed against it:
    // origin'[d] = snap^-1[origin[d]]; the snapshot is then in the host's order
    permute_host_only(origin_snap_host_);
    std::uint32_t* inv = work_u32(0);
    launch_.for_each(n_, InvertBody{origin_snap_, inv});
    launch_.for_each(n_, ComposeBody{inv, origin_, work_u32(1)});
    launch_.copy(origin_, work_u32(1), n_ * sizeof(std::uint32_t));
    launch_.for_each(n_, IotaBody{origin_snap_});
  }
  std::size_t state_bytes() const override { return launch_.bytes_in_use() - snapshot_bytes_; }
  std::size_t snapshot_bytes() const override { return snapshot_bytes_; }

 private:
  // --- the mirror ---------------------------------------------------------------------------------
  struct Mirror {
    FieldBase* host;
    void* dev;      // device array (null: host-only)
    void* snap;     // last-good copy (checkpointed device fields)
    std::size_t elem;
    bool checkpointed;
  };

  int find(const std::string& name) const {
    for (std::size_t k = 0; k < f_.size(); ++k)
      if (f_[k].host->name() == name) return int(k);
    return -1;
  }
  int need(const std::string& name) const {
    const int k = find(name);
    if (k < 0 || !f_[std::size_t(k)].dev) throw std::logic_error("device backend: no device field '" + name + "'");
    return k;
  }
  Vec<D>* vec(int k) const { return static_cast<Vec<D>*>(f_[std::size_t(k)].dev); }
  Real* real(int k) const { return static_cast<Real*>(f_[std::size_t(k)].dev); }
  const std::int32_t* kind() const { return static_cast<const std::int32_t*>(f_[std::size_t(ikind_)].dev); }
  std::uint32_t* work_u32(int slot) const { return reinterpret_cast<std::uint32_t*>(work_) + std::size_t(slot) * n_; }

  // host-only fields reordered by perm (new[k] = old[perm[k]]); Field::permute takes a scratch sized for it
  void permute_host_only(const std::vector<std::uint32_t>& perm) {
    std::size_t bytes = 0;
    for (const auto& f : f_)
      if (!f.dev) bytes = std::max(bytes, f.elem * n_);
    if (permute_scratch_.size() < bytes) permute_scratch_.resize(bytes);
    for (auto& f : f_)
      if (!f.dev) f.host->permute(perm, permute_scratch_);
  }
  void allocate() {
    const auto& fields = s_.fields;
    std::size_t max_elem = 8;
    for (std::size_t k = 0; k < fields.size(); ++k) {
      FieldBase* h = fields[k];
      Mirror m{h, nullptr, nullptr, h->bytes_per_particle(), h->flags().checkpointed};
      if (m.elem % 4 != 0) throw std::logic_error("device backend: field '" + h->name() + "' is not made of 32-bit words");
      if (!s_.host_only[k]) {
        m.dev = launch_.alloc(m.elem * n_);
        max_elem = std::max(max_elem, m.elem);
        if (m.checkpointed) {
          m.snap = launch_.alloc(m.elem * n_);
          snapshot_bytes_ += m.elem * n_;
        }
      } else {
        any_host_only_ = true;
      }
      f_.push_back(m);
    }
    ix_ = need("position");
    iv_ = need("velocity");
    ia_ = need("acceleration");
    irho_ = need("density");
    idrho_ = need("density_rate");
    ip_ = need("pressure");
    imass_ = need("mass");
    ikind_ = need("kind");
    iwall_v_ = find("wall_velocity");
    inormal_ = find("normal");
    if (inormal_ >= 0 && !f_[std::size_t(inormal_)].dev) inormal_ = -1;
    for (const auto& name : s_.position_like) position_like_.push_back(need(name));
    if (position_like_.size() > std::size_t(WrapBody<D>::kMaxPositionLike))
      throw std::logic_error("device backend: too many position-like fields");
    if (s_.integrator == DeviceIntegratorKind::VerletDsph) {
      iv_prev_ = need("verlet_dsph_v_prev");
      irho_prev_ = need("verlet_dsph_rho_prev");
    }
    if (s_.integrator == DeviceIntegratorKind::Variational && s_.alpha != 1.0) {
      ia2_ = need("variational_a2");
      imid_ = need("variational_midpoint");
      ivit_ = need("variational_v_iterate");
      ivnew_ = need("variational_v_next");
      ia1_ = need("variational_a1");
      igamma_ = need("variational_wall_force");
      irho1_ = need("variational_rho_iterate");
      ip1_ = need("variational_p_iterate");
      idrho1_ = need("variational_drho");
    }
    // persistent: sorted cell key and the origin of every particle (host-only fields), its saved copy
    key_ = static_cast<std::uint32_t*>(launch_.alloc(n_ * 4));
    origin_ = static_cast<std::uint32_t*>(launch_.alloc(n_ * 4));
    origin_snap_ = static_cast<std::uint32_t*>(launch_.alloc(n_ * 4));
    snapshot_bytes_ += 4 * n_;
    // one work area shared by the phases that never overlap: the sort (keys in, indices in, permutation;
    // the gather buffer of the largest field over the first two) and the passes (p / rho^2, m / rho)
    const std::size_t sort_words = std::max<std::size_t>(2, max_elem / 4) + 1;
    // Antuono's delta-SPH adds the renormalised density gradient (D values) after p / rho^2 and m / rho
    const bool gradients = s_.params.diffusion == physics::DensityDiffusion::Antuono && !s_.params.riemann;
    const std::size_t pass_words = (gradients ? 2 + D : 2) * sizeof(Real) / 4;
    work_words_ = std::max(sort_words, pass_words);
    work_ = launch_.alloc(work_words_ * 4 * n_);
    // the tabulated kernel
    table_w_ = static_cast<Real*>(launch_.alloc(s_.table_w.size() * sizeof(Real)));
    table_f_ = static_cast<Real*>(launch_.alloc(s_.table_f.size() * sizeof(Real)));
    launch_.to_device(table_w_, s_.table_w.data(), s_.table_w.size() * sizeof(Real));
    launch_.to_device(table_f_, s_.table_f.data(), s_.table_f.size() * sizeof(Real));
    W_ = {s_.support, s_.params.h, s_.table_scale, table_w_, table_f_, s_.table_intervals};
    ensure_cells();
  }
  void free_all() {
    for (auto& f : f_) {
      launch_.release(f.dev);
      launch_.release(f.snap);
      f.dev = f.snap = nullptr;
    }
    for (void* p : {static_cast<void*>(key_), static_cast<void*>(origin_), static_cast<void*>(origin_snap_), work_,
                    static_cast<void*>(table_w_), static_cast<void*>(table_f_), static_cast<void*>(cell_end_)})
      launch_.release(p);
    key_ = origin_ = origin_snap_ = cell_end_ = nullptr;
    work_ = nullptr;
    table_w_ = table_f_ = nullptr;
  }
  // cell_end sized for the grid (grows when the variational skin widens the cells? no: wider cells are
  // fewer; it grows only if a configuration has more cells than any before)
  void ensure_cells() {
    if (g_.n_cells > cell_cap_) {
      launch_.release(cell_end_);
      cell_end_ = static_cast<std::uint32_t*>(launch_.alloc(g_.n_cells * sizeof(std::uint32_t)));
      cell_cap_ = g_.n_cells;
    }
    g_.key = key_;
    g_.cell_end = cell_end_;
  }

  // --- sort and bin (Simulation::sort_and_bin): wrap, keys, stable radix sort, reorder, cell ends -----
  void sort_and_bin() {
    bool any_periodic = false;
    for (int a = 0; a < D; ++a) any_periodic = any_periodic || g_.periodic[a];
    if (any_periodic) {
      WrapBody<D> w{g_, vec(ix_), {}, int(position_like_.size())};
      for (std::size_t k = 0; k < position_like_.size(); ++k) w.position_like[k] = vec(position_like_[k]);
      launch_.for_each(n_, w);
    }
    std::uint32_t* key_in = work_u32(0);
    std::uint32_t* index_in = work_u32(1);
    std::uint32_t* perm = work_u32(int(work_words_) - 1);
    launch_.for_each(n_, CellKeyBody<D>{g_, vec(ix_), key_in, index_in});
    int bits = 0;
    while (bits < 32 && (std::uint64_t(1) << bits) < g_.n_cells) ++bits;
    launch_.sort_pairs(key_in, key_, index_in, perm, n_, bits);
    // every device field, and the origin index, in the new order (gather into the work area, copy back)
    std::uint32_t* tmp = work_u32(0);
    for (auto& f : f_) {
      if (!f.dev) continue;
      const std::uint32_t words = std::uint32_t(f.elem / 4);
      launch_.for_each(n_ * words, GatherWordsBody{static_cast<const std::uint32_t*>(f.dev), tmp, perm, words});
      launch_.copy(f.dev, tmp, f.elem * n_);
    }
    launch_.for_each(n_, GatherWordsBody{origin_, tmp, perm, 1});
    launch_.copy(origin_, tmp, n_ * 4);
    if (n_ > 0) launch_.for_each(n_, CellEndBody{key_, cell_end_, std::uint32_t(n_), g_.n_cells});
  }
  void set_skin(Real skin) {
    g_ = host_.set_skin(skin);
    ensure_cells();
  }

  // --- views and passes ---------------------------------------------------------------------------------
  View view(int ix, int iv, int irho, int ip, bool with_wall_v) const {
    View s{std::span<const Vec<D>>(vec(ix), n_), std::span<const Vec<D>>(vec(iv), n_),
           std::span<const Real>(real(irho), n_), std::span<const Real>(real(ip), n_),
           std::span<const Real>(real(imass_), n_), std::span<const std::int32_t>(kind(), n_)};
    if (with_wall_v && iwall_v_ >= 0) {  // Simulation::current_view: extrapolated walls show v_w and normals
      s.wall_v = std::span<const Vec<D>>(vec(iwall_v_), n_);
      if (inormal_ >= 0) s.normal = std::span<const Vec<D>>(vec(inormal_), n_);
    }
    return s;
  }
  View current_view() const { return view(ix_, iv_, irho_, ip_, true); }

  template <class Maker>
  void pairs(const View& s, const Maker& m) {
    launch_.for_each(n_, PairBody<D, Maker>{g_, s.x.data(), rc2_, m});
  }
  Real* pressure_terms(const View& s) {
    Real* pr = reinterpret_cast<Real*>(work_);
    launch_.for_each(n_, PressureTermBody{pr, s.p.data(), s.rho.data()});
    return pr;
  }
  template <class Diff>
  const Real* volumes(const View& s) {
    if constexpr (!Diff::enabled) return nullptr;
    Real* V = reinterpret_cast<Real*>(work_) + n_;
    launch_.for_each(n_, VolumeBody{V, s.mass.data(), s.rho.data()});
    return V;
  }
  template <class Visc>
  Visc viscosity() const {
    if constexpr (std::is_same_v<Visc, physics::NoViscosity>) return {};
    else if constexpr (std::is_same_v<Visc, physics::ArtificialViscosity>) return av_;
    else if constexpr (std::is_same_v<Visc, physics::LaminarViscosity>) return lam_;
    else if constexpr (std::is_same_v<Visc, physics::RiemannDissipation>) return riemann_;
    else if constexpr (std::is_same_v<Visc, physics::RiemannAndLaminarViscosity>) return Visc(riemann_, lam_);
    else return Visc(av_, lam_);
  }
  // The diffusion policy for the state s; Antuono's delta-SPH first runs its gradient sweep (as RatesImpl's
  // diffusion(g, s)), reading the volumes `V` the pass computed.
  template <class Diff>
  Diff diffusion(const View& s, const Real* V) {
    if constexpr (std::is_same_v<Diff, physics::AntuonoDiffusion<D>>) {
      const auto& p = s_.params;
      Diff d(p.diffusion_delta, p.h, p.c0);
      Vec<D>* grad = reinterpret_cast<Vec<D>*>(reinterpret_cast<Real*>(work_) + 2 * n_);
      pairs(s, DensityGradientMaker<D>{W_, s, V, grad});
      d.grad = grad;
      return d;
    } else {
      (void)s;
      (void)V;
      return diffusion<Diff>();
    }
  }
  template <class Diff>
  Diff diffusion() const {
    const auto& p = s_.params;
    if constexpr (std::is_same_v<Diff, physics::NoDensityDiffusion>) return {};
    else if constexpr (std::is_same_v<Diff, physics::MolteniDiffusion>) return Diff(p.diffusion_delta, p.h, p.c0);
    else if constexpr (std::is_same_v<Diff, physics::RiemannDiffusion<D>>) return Diff(p.rho0, p.c0, p.gravity);
    else return Diff(p.diffusion_delta, p.h, p.c0, p.rho0, p.gravity);
  }

  using AccFn = void (*)(Backend&, const View&, Vec<D>*, const physics::RepulsiveWall&);
  using RhoFn = void (*)(Backend&, const View&, Real*);
  using FusedFn = void (*)(Backend&, const View&, Real*, Vec<D>*);

  template <class Visc, BM M>
  static void run_acc(Backend& b, const View& s, Vec<D>* a, const physics::RepulsiveWall& wall) {
    const Real* pr = b.pressure_terms(s);
    b.pairs(s, AccelerationMaker<D, Visc, M>{b.W_, b.template viscosity<Visc>(), wall, b.soft_, s, b.host_.body_acceleration(), a, pr});
  }
  template <BM M, class Diff>
  static void run_drho(Backend& b, const View& s, Real* drho) {
    const Real* V = b.template volumes<Diff>(s);
    b.pairs(s, DensityRateMaker<D, M, Diff>{b.W_, s, drho, b.template diffusion<Diff>(s, V), V});
  }
  template <BM M>
  static void run_sum(Backend& b, const View& s, Real* rho) {
    b.pairs(s, SummationMaker<D, M>{b.W_, s, rho});
  }
  template <class Visc, BM MD, BM MA, class Diff>
  static void run_fused(Backend& b, const View& s, Real* drho, Vec<D>* a) {
    const Real* pr = b.pressure_terms(s);
    const Real* V = b.template volumes<Diff>(s);
    const Diff diff = b.template diffusion<Diff>(s, V);
    b.pairs(s, FusedMaker<D, Visc, MD, MA, Diff>{b.W_, b.template viscosity<Visc>(), b.wall_, b.soft_, s,
                                                 b.host_.body_acceleration(), drho, a, diff, V, pr});
  }

  // one instantiation per term combination, chosen once (RatesImpl's pick_*; soft walls and mDBC are refused
  // at start). The Riemann solver's dissipation comes with its continuity term (RiemannDiffusion) in place
  // of any delta-SPH, as RatesImpl does.
  template <class Visc>
  void pick_for_viscosity() {
    switch (s_.params.boundary) {
      case BM::Repulsive:
        acc_fn_ = &run_acc<Visc, BM::Repulsive>;
        fused_for_diffusion<Visc, BM::Repulsive, BM::Repulsive>();
        return;
      case BM::Dynamic:
        acc_fn_ = &run_acc<Visc, BM::DummyAdami>;
        fused_for_diffusion<Visc, BM::Dynamic, BM::DummyAdami>();
        return;
      case BM::DummyAdami:
        acc_fn_ = &run_acc<Visc, BM::DummyAdami>;
        fused_for_diffusion<Visc, BM::DummyAdami, BM::DummyAdami>();
        return;
      case BM::SoftRepulsive:
      case BM::Mdbc: break;  // refused at start (check_device_scene)
    }
    throw std::logic_error("device backend: a wall model check_device_scene refuses reached the backend");
  }
  template <class Visc>
  static constexpr bool is_riemann =
      std::is_same_v<Visc, physics::RiemannDissipation> || std::is_same_v<Visc, physics::RiemannAndLaminarViscosity>;
  template <class Visc, BM MD, BM MA>
  void fused_for_diffusion() {
    if constexpr (is_riemann<Visc>) {
      fused_fn_ = &run_fused<Visc, MD, MA, physics::RiemannDiffusion<D>>;
      return;
    } else {
      fused_for_delta_sph<Visc, MD, MA>();
    }
  }
  template <class Visc, BM MD, BM MA>
  void fused_for_delta_sph() {
    switch (s_.params.diffusion) {
      case physics::DensityDiffusion::None: fused_fn_ = &run_fused<Visc, MD, MA, physics::NoDensityDiffusion>; return;
      case physics::DensityDiffusion::Molteni: fused_fn_ = &run_fused<Visc, MD, MA, physics::MolteniDiffusion>; return;
      case physics::DensityDiffusion::Fourtakas:
        fused_fn_ = &run_fused<Visc, MD, MA, physics::FourtakasDiffusion<D>>;
        return;
      case physics::DensityDiffusion::Antuono:
        fused_fn_ = &run_fused<Visc, MD, MA, physics::AntuonoDiffusion<D>>;
        return;
    }
  }
  template <BM M>
  void density_for_wall() {
    sum_fn_ = &run_sum<M>;
    if (s_.params.riemann) {
      drho_fn_ = &run_drho<M, physics::RiemannDiffusion<D>>;
      return;
    }
    switch (s_.params.diffusion) {
      case physics::DensityDiffusion::None: drho_fn_ = &run_drho<M, physics::NoDensityDiffusion>; break;
      case physics::DensityDiffusion::Molteni: drho_fn_ = &run_drho<M, physics::MolteniDiffusion>; break;
      case physics::DensityDiffusion::Fourtakas: drho_fn_ = &run_drho<M, physics::FourtakasDiffusion<D>>; break;
      case physics::DensityDiffusion::Antuono: drho_fn_ = &run_drho<M, physics::AntuonoDiffusion<D>>; break;
    }
  }
  void pick_passes() {
    const auto& p = s_.params;
    if (p.riemann && p.laminar_viscosity) pick_for_viscosity<physics::RiemannAndLaminarViscosity>();
    else if (p.riemann) pick_for_viscosity<physics::RiemannDissipation>();
    else if (p.artificial_viscosity && p.laminar_viscosity) pick_for_viscosity<physics::ArtificialAndLaminarViscosity>();
    else if (p.artificial_viscosity) pick_for_viscosity<physics::ArtificialViscosity>();
    else if (p.laminar_viscosity) pick_for_viscosity<physics::LaminarViscosity>();
    else pick_for_viscosity<physics::NoViscosity>();
    switch (p.boundary) {
      case BM::Repulsive: density_for_wall<BM::Repulsive>(); break;
      case BM::Dynamic: density_for_wall<BM::Dynamic>(); break;
      case BM::DummyAdami: density_for_wall<BM::DummyAdami>(); break;
      case BM::SoftRepulsive:
      case BM::Mdbc: break;  // refused at start, and by pick_for_viscosity above
    }
    adami_ = p.boundary == BM::DummyAdami;
    dynamic_walls_ = p.boundary == BM::Dynamic;
    summation_ = p.density == physics::DensityMode::Summation;
  }

  // --- the services of Simulation, on the device ----------------------------------------------------------
  void update_pressure() {
    launch_.for_each(n_, PressureBody{real(ip_), real(irho_), s_.eos});
    if (adami_) {  // dummy walls (Adami 2012): boundary pressure, density and viscous velocity from the fluid
      const View s = current_view();
      const bool free_slip = s_.params.wall_slip == physics::WallSlip::FreeSlip;
      physics::WallGeometry<D> geo;
      geo.normal = inormal_ >= 0 ? vec(inormal_) : nullptr;
      pairs(s, AdamiWallMaker<D>{W_, s, geo, host_.body_acceleration(), s_.eos,
                                 free_slip, real(ip_), real(irho_), vec(iwall_v_)});
    }
  }
  void update_density_after_move(Real dt) {
    const View s = current_view();
    if (summation_) {
      sum_fn_(*this, s, real(irho_));
    } else {
      drho_fn_(*this, s, real(idrho_));
      launch_.for_each(n_, DensityStepBody{real(irho_), real(irho_), real(idrho_), kind(), dt, dynamic_walls_});
    }
    update_pressure();
  }
  double choose_dt() {
    if (host_.fixed_dt()) return host_.choose_dt(0, 0);
    const double vmax = launch_.template reduce<MaxOp>(n_, FluidNormBody<D>{vec(iv_), kind()});
    const double amax = launch_.template reduce<MaxOp>(n_, FluidNormBody<D>{vec(ia_), kind()});
    return host_.choose_dt(vmax, amax);
  }

  // --- verlet (seed eq. 60-62) and symplectic_euler: the same step on the device ------------------------
  void kick_drift_step() {
    acc_fn_(*this, current_view(), vec(ia_), wall_);  // eq. (59)
    const double dtd = choose_dt();
    host_.set_dt(dtd);
    const Real dt = Real(dtd);
    launch_.for_each(n_, KickDriftBody<D>{vec(ix_), vec(iv_), vec(ia_), kind(), dt});
    sort_and_bin();
    update_density_after_move(dt);
  }

  // --- verlet_dsph (integrators/verlet_dsph.hpp) ------------------------------------------------------------
  void verlet_dsph_step(DeviceStepState& st) {
    fused_fn_(*this, current_view(), real(idrho_), vec(ia_));
    const double dtd = choose_dt();
    host_.set_dt(dtd);
    const Real dt = Real(dtd);
    const bool euler = st.steps_since_euler < 0 || st.steps_since_euler + 1 >= s_.euler_every;
    st.steps_since_euler = euler ? 0 : st.steps_since_euler + 1;
    launch_.for_each(n_, VerletDsphBody<D>{vec(ix_), vec(iv_), real(irho_), vec(ia_), real(idrho_), vec(iv_prev_),
                                           real(irho_prev_), kind(), dt, Real(0.5) * dt * dt,
                                           euler ? dt : Real(2) * dt, euler, dynamic_walls_});
    sort_and_bin();
    update_pressure();
  }

  // --- variational (integrators/variational.cpp, seed eq. 63-65, Algorithm 1) ----------------------------
  static constexpr int kDivergenceWindow = 3;
  static constexpr int kMaxHalvings = 12;
  static constexpr int kRegrowAfter = 100;

  bool ensure_skin(Real displacement) {
    if (Real(2) * displacement <= host_.skin()) return true;
    const Real old = host_.skin();
    for (const Real skin : {std::max(Real(2) * old, Real(4) * displacement), Real(2.0001) * displacement}) {
      try {
        set_skin(skin);
        sort_and_bin();
        return true;
      } catch (const InputError&) {  // cells too large for a (periodic) domain: the step moves too far
      }
    }
    set_skin(old);
    sort_and_bin();
    return false;
  }
  Real make_midpoint(int iv, Real s) {
    const Real vmax = Real(launch_.template reduce<MaxOp>(n_, FluidSquaredNormBody<D>{vec(iv), kind()}));
    const Real shift = std::abs(s) * std::sqrt(vmax);
    if (!std::isfinite(shift) || !ensure_skin(shift)) return -1;
    launch_.for_each(n_, MidpointBody<D>{vec(imid_), vec(ix_), vec(iv), kind(), s});
    return shift;
  }
  void eval_midpoint(int iv, Real dt_rho, Vec<D>* a_out) {
    launch_.copy(real(irho1_), real(irho_), n_ * sizeof(Real));
    // extrapolated walls: their state of q_k (variational_step) and the velocities the viscosity sees, as the
    // host's VariationalIntegrator::eval_midpoint
    const View base = view(imid_, iv, irho_, ip_, true);
    if (summation_) {
      sum_fn_(*this, base, real(irho1_));  // seed eq. (20)/(30) at the midpoint
    } else {
      drho_fn_(*this, base, real(idrho1_));  // eq. (67)-(68), standard sign
      launch_.for_each(n_, DensityStepBody{real(irho1_), real(irho_), real(idrho1_), kind(), dt_rho, dynamic_walls_});
    }
    launch_.for_each(n_, PressureBody{real(ip1_), real(irho1_), s_.eos});  // eq. (26)-(27), (35)-(36)
    acc_fn_(*this, view(imid_, iv, irho1_, ip1_, true), a_out, s_.variational_explicit ? wall_ : no_wall_);
  }
  void compute_gamma() {
    if (!s_.variational_wall) return;
    const View s = current_view();
    pairs(s, WallOnlyMaker<D>{wall_, s, vec(igamma_), s_.support});  // Gamma_k, eq. (58)
  }
  void rebuild_previous(double dt_old, double dt_new) {
    const double alpha = s_.alpha;
    if (make_midpoint(iv_, Real(-(1 - alpha) * dt_new)) < 0)
      throw NumericalError("variational: at t = " + std::to_string(host_.time()) +
                           " s the previous interval's midpoint moves particles farther than the neighbour grid "
                           "can cover (dt " + std::to_string(dt_new) + " s too large)");
    eval_midpoint(iv_, Real((1 - alpha) * (dt_old - dt_new)), vec(ia2_));
    launch_.copy(real(irho_), real(irho1_), n_ * sizeof(Real));
    launch_.copy(real(ip_), real(ip1_), n_ * sizeof(Real));
  }
  bool apply_F(Real dt, int iv_in, int iv_out) {
    const double alpha = s_.alpha;
    if (make_midpoint(iv_in, Real(alpha) * dt) < 0) return false;  // (1-alpha) q_k + alpha q_{k+1}, eq. (20)-(21)
    eval_midpoint(iv_in, dt, vec(ia1_));
    launch_.for_each(n_, ApplyFBody<D>{vec(iv_out), vec(iv_), vec(ia1_), vec(ia2_), vec(igamma_), kind(), dt,
                                       Real(1 - alpha), Real(alpha)});
    return true;
  }
  bool solve(Real dt, DeviceStepReport& rep, std::string& history) {
    rep = {};
    residuals_.clear();
    if (s_.variational_explicit) {  // alpha = 0, summation, no viscosity: a1 at q_k does not depend on q_{k+1}
      rep.iterations = 1;
      if (apply_F(dt, iv_, ivnew_)) return true;
      history = "a1 at q_k could not be evaluated";
      return false;
    }
    // explicit predictor q_{k+1;0} = 2 q_k - q_{k-1} + dt^2 (a2 + Gamma_k) (a1 taken as a2)
    launch_.for_each(n_, PredictorBody<D>{vec(ivit_), vec(iv_), vec(ia2_), vec(igamma_), kind(), dt});
    int diverging = 0;
    double prev = 0;
    bool too_far = false;
    const double tol = s_.fp_tolerance;
    for (int j = 1; j <= s_.fp_max_iterations; ++j) {
      if (!apply_F(dt, ivit_, ivnew_)) {  // q_{k+1;j} = F(q_{k+1;j-1}, q_k, q_{k-1}), eq. (40)
        too_far = true;
        break;
      }
      const double r2 = launch_.template reduce<MaxOp>(n_, FluidSquaredDifferenceBody<D>{vec(ivnew_), vec(ivit_), kind()});
      const double r = double(dt) * std::sqrt(r2);  // max_i |q_{k+1;j} - q_{k+1;j-1}|
      residuals_.push_back(r);
      const double c = (j > 1 && prev > 0) ? r / prev : 0.0;
      rep.iterations = j;
      rep.residual = r;
      rep.contraction = std::max(rep.contraction, c);
      if (r <= tol) return true;
      diverging = (j > 1 && c >= 1.0) ? diverging + 1 : 0;
      if (diverging >= kDivergenceWindow) break;
      prev = r;
      std::swap(f_[std::size_t(ivit_)].dev, f_[std::size_t(ivnew_)].dev);  // no copy (host: vector swap)
    }
    std::ostringstream o;
    o.precision(3);
    o << (too_far ? std::string("fixed-point iterate moves particles farther than the neighbour grid can cover")
        : diverging >= kDivergenceWindow ? "fixed point diverging (contraction >= 1 for " +
                                               std::to_string(kDivergenceWindow) + " iterations)"
                                         : "fixed point not converged in " + std::to_string(s_.fp_max_iterations) +
                                               " iterations")
      << " (alpha " << s_.alpha << ", dt " << dt << " s, tolerance " << tol << " m); residuals [m]:";
    for (double r : residuals_) o << ' ' << r;
    history = o.str();
    return false;
  }
  DeviceStepReport variational_step(DeviceStepState& st) {
    if (s_.alpha == 1.0) {  // the explicit Verlet scheme, eq. (60)-(62)
      kick_drift_step();
      return {};
    }
    double dt = choose_dt() / double(1L << st.halvings);
    if (dt != st.dt_prev && !s_.variational_explicit) rebuild_previous(st.dt_prev, dt);  // regrowth, CFL change, restart
    host_.set_dt(dt);
    // dummy walls extrapolated from the fluid at q_k once per step, where Gamma_k is evaluated (the host's
    // VariationalIntegrator::loads_at_qk)
    if (adami_) update_pressure();
    compute_gamma();
    DeviceStepReport rep;
    std::string history;
    while (!solve(Real(dt), rep, history)) {
      const std::string where = "step " + std::to_string(host_.step() + 1) + " (t = " + std::to_string(host_.time()) +
                                " s -> " + std::to_string(host_.time() + dt) + " s): ";
      if (!s_.halve_on_failure || st.halvings >= kMaxHalvings)
        throw NumericalError(where + history +
                             (s_.halve_on_failure ? "; dt already halved " + std::to_string(kMaxHalvings) + " times"
                                                  : std::string("")) +
                             ". The state is left at the last accepted step (t = " + std::to_string(host_.time()) +
                             " s); integrator.fixed_point.on_failure = \"halve_dt\" retries with smaller steps");
      ++st.halvings;
      st.steps_since_change = 0;
      const double dt_new = dt / 2;
      std::fprintf(stderr, "varsph: variational: %s%s; halving dt to %.4g s\n", where.c_str(), history.c_str(), dt_new);
      rebuild_previous(dt, dt_new);
      dt = dt_new;
      st.dt_prev = dt;
      host_.set_dt(dt);
    }
    if (rep.contraction > 0) st.last_bound = dt / std::sqrt(rep.contraction);  // eq. (54) with M1 ~ c
    rep.dt_bound = st.last_bound;
    const double alpha = s_.alpha;
    launch_.for_each(n_, AcceptBody<D>{vec(ix_), vec(iv_), vec(ia_), vec(ia1_), vec(ia2_), vec(ivnew_), vec(igamma_),
                                       real(irho_), real(ip_), real(irho1_), real(ip1_), kind(), Real(1 - alpha),
                                       Real(alpha), Real(dt)});
    st.dt_prev = dt;
    sort_and_bin();
    if (st.halvings > 0 && ++st.steps_since_change >= kRegrowAfter) {
      --st.halvings;  // the next step sees dt != dt_prev and rebuilds the previous interval
      st.steps_since_change = 0;
      std::fprintf(stderr, "varsph: variational: growing dt back to %.4g s at t = %g s\n",
                   choose_dt() / double(1L << st.halvings), host_.time() + dt);
    }
    return rep;
  }

  // --- members --------------------------------------------------------------------------------------------
  Launch launch_;
  DeviceSetup<D> s_;
  HostSide<D>& host_;
  std::size_t n_;
  std::size_t capacity_;  // particles the device arrays hold (the initial count)
  GridView<D> g_{};
  Real rc2_ = 0;
  physics::RepulsiveWall wall_{0, 1, 12, 4}, no_wall_{0, 1, 12, 4};
  physics::SoftRepulsiveWall soft_{0, 1, 1, 1};
  physics::ArtificialViscosity av_{0, 0, 1, 1};
  physics::LaminarViscosity lam_{0, 1};
  physics::RiemannDissipation riemann_{1, 1, 0};
  DeviceKernel<D> W_{};
  std::vector<Mirror> f_;
  bool any_host_only_ = false;
  int ix_ = -1, iv_ = -1, ia_ = -1, irho_ = -1, idrho_ = -1, ip_ = -1, imass_ = -1, ikind_ = -1;
  int iwall_v_ = -1, inormal_ = -1;
  int iv_prev_ = -1, irho_prev_ = -1;
  int ia2_ = -1, imid_ = -1, ivit_ = -1, ivnew_ = -1, ia1_ = -1, igamma_ = -1, irho1_ = -1, ip1_ = -1, idrho1_ = -1;
  std::vector<int> position_like_;
  std::uint32_t* key_ = nullptr;
  std::uint32_t* origin_ = nullptr;
  std::uint32_t* origin_snap_ = nullptr;
  std::uint32_t* cell_end_ = nullptr;
  std::uint64_t cell_cap_ = 0;
  void* work_ = nullptr;
  std::size_t work_words_ = 0;
  Real* table_w_ = nullptr;
  Real* table_f_ = nullptr;
  std::size_t snapshot_bytes_ = 0;
  bool device_ahead_ = false, snapshot_valid_ = false;
  bool adami_ = false, dynamic_walls_ = false, summation_ = false;
  AccFn acc_fn_ = nullptr;
  RhoFn drho_fn_ = nullptr, sum_fn_ = nullptr;
  FusedFn fused_fn_ = nullptr;
  std::vector<double> residuals_;
  std::vector<std::uint32_t> origin_host_, origin_snap_host_;
  bool download_pending_ = false;
  std::vector<std::byte> permute_scratch_;
};

}  // namespace varsph::exec
