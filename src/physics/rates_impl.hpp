#pragma once
// RatesImpl<D, Kernel>: the compiled passes for one kernel. The viscosity x wall-model combination of
// the acceleration pass and the wall-model x density-diffusion combination of the continuity pass are
// chosen once (function pointers to separately instantiated passes), so the number of instantiations is
// a sum over policies, not a product. Included only by the per-kernel translation units rates_<kernel>.cpp.
#include <cmath>
#include <numbers>
#include <vector>

#include "core/first_touch.hpp"
#include "core/team.hpp"
#include "kernels/tabulated.hpp"
#include "physics/pair_loop.hpp"
#include "physics/passes.hpp"
#include "physics/rates.hpp"
#include "physics/wall_mdbc.hpp"
#include "physics/simd/isa.hpp"
#include "physics/simd/vector_sweep.hpp"

namespace varsph::physics {

template <int D, class Kernel>
class RatesImpl final : public Rates<D> {
 public:
  RatesImpl(const PhysicsParams<D>& p, Kernel kernel)
      : p_(p), W_(kernel), wall_(p.wall_D, p.wall_r0, p.wall_n1, p.wall_n2),
        soft_(p.soft_wall_coef, p.c0, p.dx, p.h),
        av_(p.av_alpha, p.av_beta, p.c0, p.h, p.av_eps), riemann_(p.rho0, p.c0, p.riemann_eta), lam_(p.nu, p.h),
        stress_(p.as_eps, W_.w_r2(p.dx * p.dx), p.as_n), eos_(p.rho0, p.c0, p.background_pressure) {
    pick_acceleration();
    pick_density();
    if constexpr (std::is_same_v<Kernel, kernels::Tabulated<D>>) pick_fused();
    set_time(0);
  }

  void density_rate(const NeighborGrid<D>& g, const ParticleView<D>& s, Real* drho) const override {
    drho_fn_(*this, g, s, drho);
  }
  void summation_density(const NeighborGrid<D>& g, const ParticleView<D>& s, Real* rho) const override {
    sum_fn_(*this, g, s, rho);
  }
  void acceleration(const NeighborGrid<D>& g, const ParticleView<D>& s, Vec<D>* a) const override {
    acc_fn_(*this, g, s, a);
    add_optional_accelerations(g, s, a);
  }
  void density_rate_and_acceleration(const NeighborGrid<D>& g, const ParticleView<D>& s, Real* drho,
                                     Vec<D>* a) const override {
    if (!fused_fn_) return Rates<D>::density_rate_and_acceleration(g, s, drho, a);
    fused_fn_(*this, g, s, drho, a);
    add_optional_accelerations(g, s, a);
  }
  bool fused() const override { return fused_fn_ != nullptr; }
  bool splits_by_blocks() const override {  // see Rates; the damping window depends on the time
    return !damping_on_ && p_.diffusion != DensityDiffusion::Antuono && p_.boundary != BoundaryModel::Mdbc;
  }
  const char* simd() const override { return simd::to_string(vector_covered_ ? isa_ : simd::Isa::Scalar); }
  // artificial stress and damping, each its own loop and only when named
  void add_optional_accelerations(const NeighborGrid<D>& g, const ParticleView<D>& s, Vec<D>* a) const {
    if (p_.tensile == TensileFix::ArtificialStress) {
      ArtificialStressPass<D, Kernel> pass{W_, stress_, s, a};
      for_each_particle_pairs<D>(g, s.x, W_.support(), pass);
    }
    if (damping_on_) {
      // viscous damping F = -mu v (foundation notes, "Alternative viscous damping term"), per particle
      const Real mu = p_.damping_mu;
      for_each_particle(s.size(), [&](std::size_t i) {
        if (s.kind[i] == kFluid) a[i] -= mu * s.v[i];
      });
    }
  }
  void boundary_reaction(const NeighborGrid<D>& g, const ParticleView<D>& s, Vec<D>* force,
                         BoundaryFilter only) const override {
    react_fn_(*this, g, s, force, only);
  }
  Real support() const override { return W_.support(); }
  Real kernel_w(Real r) const override { return r < W_.support() ? W_.w_r2(r * r) : Real(0); }

  void set_time(double t) override {
    Real ramp = 1;
    if (p_.gravity_ramp > 0 && t < double(p_.gravity_ramp))  // smooth ramp g (1 - cos(pi t/T)) / 2
      ramp = Real(0.5 * (1.0 - std::cos(std::numbers::pi * t / double(p_.gravity_ramp))));
    g_eff_ = ramp * p_.gravity + p_.body_force;
    damping_on_ = p_.damping && t < double(p_.damping_until);
  }
  Vec<D> body_acceleration() const override { return g_eff_; }

  bool update_walls(const NeighborGrid<D>& g, const ParticleView<D>& s, const WallGeometry<D>& geo, Real* p,
                    Real* rho, Vec<D>* vw) const override {
    const bool free_slip = p_.wall_slip == WallSlip::FreeSlip;
    if (p_.boundary == BoundaryModel::Mdbc) {  // English et al. 2022, ghost nodes (physics/wall_mdbc.hpp)
      const MdbcWall<D, Kernel> wall{W_, g, s, geo, g_eff_, eos_, p_.mdbc_extrapolation, free_slip, p, rho, vw};
      for_each_particle(s.size(), wall);
      return true;
    }
    if (p_.boundary != BoundaryModel::DummyAdami && p_.boundary != BoundaryModel::SoftRepulsive) return false;
    AdamiWallPass<D, Kernel> pass{W_, s, geo, g_eff_, eos_, free_slip, p, rho, vw};
    for_each_particle_pairs<D>(g, s.x, W_.support(), pass);
    return true;
  }
  bool xsph_enabled() const override { return p_.xsph_eps > 0; }
  void xsph(const NeighborGrid<D>& g, const ParticleView<D>& s, Vec<D>* out) const override {
    XsphPass<D, Kernel> pass{W_, s, p_.xsph_eps, out};
    for_each_particle_pairs<D>(g, s.x, W_.support(), pass);
  }
  bool shifting_enabled() const override { return p_.shifting.enabled; }
  void shifting(const NeighborGrid<D>& g, const ParticleView<D>& s, Real dt, Vec<D>* out) const override {
    Real vmax = 0;  // global max fluid speed ("max" mode; Sun 2017), a max: order-independent
    if (p_.shifting.global_speed)
      for (std::size_t i = 0; i < s.size(); ++i)
        if (s.kind[i] == kFluid) vmax = std::max(vmax, s.v[i].norm());
    if (p_.shifting.global_speed) vmax = this->global_max(vmax);  // over every rank (distributed runs)
    ShiftingPass<D, Kernel> pass{W_, s, p_.shifting, p_.h, dt, p_.rho0, p_.shifting.max_shift * p_.dx,
                                 Real(1) / W_.w_r2(p_.dx * p_.dx), vmax, out};
    for_each_particle_pairs<D>(g, s.x, W_.support(), pass);
  }

 private:
  using AccFn = void (*)(const RatesImpl&, const NeighborGrid<D>&, const ParticleView<D>&, Vec<D>*);
  using ReactFn = void (*)(const RatesImpl&, const NeighborGrid<D>&, const ParticleView<D>&, Vec<D>*, BoundaryFilter);
  using RhoFn = void (*)(const RatesImpl&, const NeighborGrid<D>&, const ParticleView<D>&, Real*);

  template <class Visc>
  Visc viscosity() const {
    if constexpr (std::is_same_v<Visc, NoViscosity>) return {};
    else if constexpr (std::is_same_v<Visc, ArtificialViscosity>) return av_;
    else if constexpr (std::is_same_v<Visc, LaminarViscosity>) return lam_;
    else if constexpr (std::is_same_v<Visc, RiemannDissipation>) return riemann_;
    else if constexpr (std::is_same_v<Visc, RiemannAndLaminarViscosity>) return Visc(riemann_, lam_);
    else return Visc(av_, lam_);
  }

  // p / rho^2 of every particle, once per pass instead of once per pair (scratch grows once)
  const Real* pressure_terms(const ParticleView<D>& s) const {
    first_touch_resize(p_over_rho2_, s.size());
    Real* pr = p_over_rho2_.data();
    for_each_particle(s.size(), [&](std::size_t i) { pr[i] = s.p[i] / (s.rho[i] * s.rho[i]); });
    return pr;
  }
  // m / rho of every particle for the density-diffusion term (none without it)
  template <class Diff>
  const Real* volumes(const ParticleView<D>& s) const {
    if constexpr (!Diff::enabled) return nullptr;
    first_touch_resize(volume_, s.size());
    Real* V = volume_.data();
    for_each_particle(s.size(), [&](std::size_t i) { V[i] = s.mass[i] / s.rho[i]; });
    return V;
  }
  // the vectorised sweep where it covers the pass (physics/simd/), else the scalar one (the reference)
  template <class Pass>
  void sweep(const NeighborGrid<D>& g, const ParticleView<D>& s, Pass& pass) const {
    if (!simd::vector_sweep<D>(isa_, g, pass, lists_for(g))) for_each_particle_pairs<D>(g, s.x, W_.support(), pass);
  }
  // One list cache per grid the passes meet, for the last two grids: a distributed run sweeps its interior
  // and its boundary blocks as two grids in turn (parallel/block_split.hpp), which one cache keyed by
  // the grid would never reuse. One process has one grid: lists_[0].
  // Chosen once per team (core/team.hpp): every thread of a step's region then sweeps with the same cache.
  simd::ListCache* lists_for(const NeighborGrid<D>& g) const {
    team_single([&] {
      for (int k = 0; k < 2; ++k)
        if (list_grid_[k] == &g) {
          list_pick_ = k;
          return;
        }
      list_pick_ = list_next_;
      list_next_ ^= 1;
      list_grid_[list_pick_] = &g;
    });
    return &lists_[list_pick_];
  }
  template <class Visc, BoundaryModel M>
  static void run_acc(const RatesImpl& r, const NeighborGrid<D>& g, const ParticleView<D>& s, Vec<D>* a) {
    const Visc visc = r.template viscosity<Visc>();
    AccelerationPass<D, Kernel, Visc, M> pass{r.W_, visc, r.wall_, s, r.g_eff_, a, &r.soft_, r.pressure_terms(s)};
    r.sweep(g, s, pass);
  }
  // force of the fluid on boundary particles from the same pair terms (probes)
  template <class Visc, BoundaryModel M>
  static void run_react(const RatesImpl& r, const NeighborGrid<D>& g, const ParticleView<D>& s, Vec<D>* f,
                        BoundaryFilter only) {
    const Visc visc = r.template viscosity<Visc>();
    using Acc = AccelerationPass<D, Kernel, Visc, M>;
    const Acc acc{r.W_, visc, r.wall_, s, r.g_eff_, nullptr, &r.soft_, r.pressure_terms(s)};
    BoundaryReactionPass<D, Acc> pass{acc, s, f, only};
    for_each_particle_pairs<D>(g, s.x, r.W_.support(), pass);
  }
  // the fused continuity + acceleration sweep (FusedRatesPass), same terms as run_drho + run_acc
  // the fused continuity + acceleration sweep (FusedRatesPass): MD is the wall model of the continuity
  // pass, MA that of the acceleration pass (dynamic walls: Dynamic / DummyAdami, as pick_* choose)
  template <class Visc, BoundaryModel MD, BoundaryModel MA, class Diff>
  static void run_fused(const RatesImpl& r, const NeighborGrid<D>& g, const ParticleView<D>& s, Real* drho,
                        Vec<D>* a) {
    const Visc visc = r.template viscosity<Visc>();
    using Dens = DensityRatePass<D, Kernel, MD, Diff>;
    using Accel = AccelerationPass<D, Kernel, Visc, MA>;
    const Real* V = r.template volumes<Diff>(s);  // before the policy: the renormalised gradient reads them
    const Dens dens{r.W_, s, drho, r.template diffusion<Diff>(g, s), V};
    const Accel accel{r.W_, visc, r.wall_, s, r.g_eff_, a, &r.soft_, r.pressure_terms(s)};
    FusedRatesPass<D, Dens, Accel> pass{dens, accel};
    r.sweep(g, s, pass);
  }
  template <BoundaryModel M, class Diff>
  static void run_drho(const RatesImpl& r, const NeighborGrid<D>& g, const ParticleView<D>& s, Real* drho) {
    const Real* V = r.template volumes<Diff>(s);
    DensityRatePass<D, Kernel, M, Diff> pass{r.W_, s, drho, r.template diffusion<Diff>(g, s), V};
    r.sweep(g, s, pass);
  }
  template <BoundaryModel M>
  static void run_sum(const RatesImpl& r, const NeighborGrid<D>& g, const ParticleView<D>& s, Real* rho) {
    SummationDensityPass<D, Kernel, M> pass{r.W_, s, rho};
    for_each_particle_pairs<D>(g, s.x, r.W_.support(), pass);
  }
  // The diffusion policy for the state s; the renormalised delta-SPH first runs its gradient sweep.
  template <class Diff>
  Diff diffusion(const NeighborGrid<D>& g, const ParticleView<D>& s) const {
    if constexpr (std::is_same_v<Diff, AntuonoDiffusion<D>>) {
      Diff d(p_.diffusion_delta, p_.h, p_.c0);
      first_touch_resize(grad_rho_, s.size());  // inside a step region: resized once (core/team.hpp)
      RenormalisedDensityGradientPass<D, Kernel> pass{W_, s, volume_.data(), grad_rho_.data()};
      for_each_particle_pairs<D>(g, s.x, W_.support(), pass);
      // a distributed run: the ghosts get their owners' gradients (eq. 10 reads grad_j of every neighbour)
      if (this->refresh_ghosts)
        team_single([&] { this->refresh_ghosts(grad_rho_.data(), sizeof(Vec<D>), grad_rho_.size()); });
      d.grad = grad_rho_.data();
      return d;
    } else {
      (void)g;
      (void)s;
      return diffusion<Diff>();
    }
  }
  template <class Diff>
  Diff diffusion() const {
    if constexpr (std::is_same_v<Diff, NoDensityDiffusion>) return {};
    else if constexpr (std::is_same_v<Diff, RiemannDiffusion<D>>) return Diff(p_.rho0, p_.c0, p_.gravity);
    else if constexpr (std::is_same_v<Diff, MolteniDiffusion>) return Diff(p_.diffusion_delta, p_.h, p_.c0);
    else return Diff(p_.diffusion_delta, p_.h, p_.c0, p_.rho0, p_.gravity);
  }

  // true when the vectorised sweep covers this pass type (physics/simd/vector_sweep.hpp)
  template <class Pass>
  static constexpr bool vectorised = simd::FluidTerms<Pass>::covered && std::is_same_v<Real, double>;
  template <class Visc, BoundaryModel M>
  void set_acc() {
    acc_fn_ = &run_acc<Visc, M>;
    react_fn_ = &run_react<Visc, M>;
    vector_covered_ = vectorised<AccelerationPass<D, Kernel, Visc, M>>;
  }
  template <class Visc>
  void acc_for_wall() {
    switch (p_.boundary) {
      case BoundaryModel::Repulsive:
        set_acc<Visc, BoundaryModel::Repulsive>();
        return;
      case BoundaryModel::Dynamic:  // same pass as dummy walls: walls are pressure particles
      case BoundaryModel::DummyAdami:
      case BoundaryModel::Mdbc:
        set_acc<Visc, BoundaryModel::DummyAdami>();
        return;
      case BoundaryModel::SoftRepulsive:
        set_acc<Visc, BoundaryModel::SoftRepulsive>();
        return;
    }
  }
  void pick_acceleration() {
    if (p_.riemann && p_.laminar_viscosity) acc_for_wall<RiemannAndLaminarViscosity>();
    else if (p_.riemann) acc_for_wall<RiemannDissipation>();
    else if (p_.artificial_viscosity && p_.laminar_viscosity) acc_for_wall<ArtificialAndLaminarViscosity>();
    else if (p_.artificial_viscosity) acc_for_wall<ArtificialViscosity>();
    else if (p_.laminar_viscosity) acc_for_wall<LaminarViscosity>();
    else acc_for_wall<NoViscosity>();
  }
  template <BoundaryModel M>
  void density_for_wall() {
    sum_fn_ = &run_sum<M>;
    if (p_.riemann) {
      drho_fn_ = &run_drho<M, RiemannDiffusion<D>>;
      return;
    }
    switch (p_.diffusion) {
      case DensityDiffusion::None: drho_fn_ = &run_drho<M, NoDensityDiffusion>; break;
      case DensityDiffusion::Molteni: drho_fn_ = &run_drho<M, MolteniDiffusion>; break;
      case DensityDiffusion::Fourtakas: drho_fn_ = &run_drho<M, FourtakasDiffusion<D>>; break;
      case DensityDiffusion::Antuono: drho_fn_ = &run_drho<M, AntuonoDiffusion<D>>; break;
    }
  }
  void pick_density() {
    switch (p_.boundary) {
      case BoundaryModel::Repulsive: density_for_wall<BoundaryModel::Repulsive>(); break;
      case BoundaryModel::Dynamic: density_for_wall<BoundaryModel::Dynamic>(); break;
      case BoundaryModel::DummyAdami:
      case BoundaryModel::Mdbc:
      case BoundaryModel::SoftRepulsive: density_for_wall<BoundaryModel::DummyAdami>(); break;
    }
  }

  // The fused sweep is compiled for the tabulated kernels only (the default and the fast path): the
  // exact kernels serve as references and keep the two separate passes.
  template <class Visc, BoundaryModel MD, BoundaryModel MA, class Diff>
  void set_fused() {
    fused_fn_ = &run_fused<Visc, MD, MA, Diff>;
    vector_covered_ = vectorised<FusedRatesPass<D, DensityRatePass<D, Kernel, MD, Diff>, AccelerationPass<D, Kernel, Visc, MA>>>;
  }
  template <class Visc, class Diff>
  void fused_for_wall() {
    switch (p_.boundary) {
      case BoundaryModel::Repulsive: return set_fused<Visc, BoundaryModel::Repulsive, BoundaryModel::Repulsive, Diff>();
      case BoundaryModel::Dynamic: return set_fused<Visc, BoundaryModel::Dynamic, BoundaryModel::DummyAdami, Diff>();
      case BoundaryModel::DummyAdami:
      case BoundaryModel::Mdbc: return set_fused<Visc, BoundaryModel::DummyAdami, BoundaryModel::DummyAdami, Diff>();
      case BoundaryModel::SoftRepulsive:
        return set_fused<Visc, BoundaryModel::DummyAdami, BoundaryModel::SoftRepulsive, Diff>();
    }
  }
  template <class Visc>
  void fused_for_diffusion() {
    if constexpr (std::is_same_v<Visc, RiemannDissipation> || std::is_same_v<Visc, RiemannAndLaminarViscosity>) {
      fused_for_wall<Visc, RiemannDiffusion<D>>();
      return;
    } else {
      fused_for_other_diffusion<Visc>();
    }
  }
  template <class Visc>
  void fused_for_other_diffusion() {
    switch (p_.diffusion) {
      case DensityDiffusion::None: fused_for_wall<Visc, NoDensityDiffusion>(); return;
      case DensityDiffusion::Molteni: fused_for_wall<Visc, MolteniDiffusion>(); return;
      case DensityDiffusion::Fourtakas: fused_for_wall<Visc, FourtakasDiffusion<D>>(); return;
      case DensityDiffusion::Antuono: fused_for_wall<Visc, AntuonoDiffusion<D>>(); return;
    }
  }
  void pick_fused() {
    if (p_.riemann && p_.laminar_viscosity) fused_for_diffusion<RiemannAndLaminarViscosity>();
    else if (p_.riemann) fused_for_diffusion<RiemannDissipation>();
    else if (p_.artificial_viscosity && p_.laminar_viscosity) fused_for_diffusion<ArtificialAndLaminarViscosity>();
    else if (p_.artificial_viscosity) fused_for_diffusion<ArtificialViscosity>();
    else if (p_.laminar_viscosity) fused_for_diffusion<LaminarViscosity>();
    else fused_for_diffusion<NoViscosity>();
  }

  PhysicsParams<D> p_;
  simd::Isa isa_ = simd::choose_isa();  // VARSPH_SIMD or the best this build and CPU have
  mutable simd::ListCache lists_[2];      // neighbour lists kept between passes over one configuration
  mutable const void* list_grid_[2] = {nullptr, nullptr};  // the grid each cache serves (lists_for)
  mutable int list_next_ = 0, list_pick_ = 0;
  Kernel W_;
  RepulsiveWall wall_;
  SoftRepulsiveWall soft_;
  ArtificialViscosity av_;
  RiemannDissipation riemann_;
  LaminarViscosity lam_;
  ArtificialStress stress_;
  TaitEos eos_;
  Vec<D> g_eff_ = Vec<D>::Zero();
  bool damping_on_ = false;
  bool vector_covered_ = false;  // the main sweep (fused, else acceleration) has a vector twin: simd()
  AccFn acc_fn_ = nullptr;
  ReactFn react_fn_ = nullptr;
  mutable std::vector<Real> p_over_rho2_;  // scratch of the acceleration pass
  mutable std::vector<Real> volume_;       // scratch of the density-diffusion term
  mutable std::vector<Vec<D>> grad_rho_;   // scratch: renormalised density gradients (Antuono diffusion)
  RhoFn drho_fn_ = nullptr, sum_fn_ = nullptr;
  using FusedFn = void (*)(const RatesImpl&, const NeighborGrid<D>&, const ParticleView<D>&, Real*, Vec<D>*);
  FusedFn fused_fn_ = nullptr;
};

template <int D, class Kernel>
std::unique_ptr<Rates<D>> make_rates_with(const PhysicsParams<D>& p, Kernel k) {
  return std::make_unique<RatesImpl<D, Kernel>>(p, k);
}

}  // namespace varsph::physics
