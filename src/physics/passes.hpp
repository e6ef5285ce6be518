#pragma once
// The pair passes, each a functor for for_each_particle_pairs, composed at compile time from the
// kernel, the viscosity policy, the wall model and the density-diffusion policy a scene names: a term
// that is off is not compiled in. Optional terms that need their own loop (XSPH, artificial stress, the
// dummy-wall extrapolation) are separate passes, run only when named.
#include <cstdint>

#include "core/real.hpp"
#include "physics/artificial_stress.hpp"
#include "physics/artificial_viscosity.hpp"
#include "physics/delta_sph.hpp"
#include "physics/density_diffusion.hpp"
#include "physics/eos.hpp"
#include "physics/laminar_viscosity.hpp"
#include "physics/boundary_filter.hpp"
#include "physics/particle_view.hpp"
#include "physics/physics_params.hpp"
#include "physics/repulsive_wall.hpp"
#include "physics/riemann.hpp"
#include "physics/soft_repulsive_wall.hpp"
#include "physics/wall_geometry.hpp"

namespace varsph::physics {

constexpr std::int32_t kFluid = 0;
constexpr std::int32_t kBoundary = 1;

// Do boundary particles count as fluid-like neighbours of fluid particles (density, pressure)?
template <BoundaryModel M>
constexpr bool walls_in_continuum = (M != BoundaryModel::Repulsive);
// Do boundary particles evolve their own density (continuity / summation)? Only dynamic walls (Crespo
// 2007); dummy walls get theirs from the fluid (AdamiWallPass).
template <BoundaryModel M>
constexpr bool walls_evolve_density = (M == BoundaryModel::Dynamic);

// Continuity equation with the standard sign (PAPER-NOTES.md on seed eq. 67-68; Monaghan 1992):
// drho_i/dt = sum_j m_j (v_i - v_j) . grad_i W_ij  [+ density diffusion, fluid-fluid pairs]
template <int D, class Kernel, BoundaryModel M, class Diffusion = NoDensityDiffusion>
struct DensityRatePass {
  static constexpr BoundaryModel model = M;
  const Kernel& W;
  const ParticleView<D>& s;
  Real* drho;
  Diffusion diff{};
  const Real* volume = nullptr;  // m_j / rho_j per particle (only read with density diffusion)
  VARSPH_HD bool active(std::size_t i) const { return s.kind[i] == kFluid || walls_evolve_density<M>; }
  VARSPH_HD Real begin(std::size_t) const { return Real(0); }
  VARSPH_HD void pair(Real& acc, std::size_t i, std::size_t j, const Vec<D>& xij, Real r2) const {
    if constexpr (!walls_in_continuum<M>)
      if (s.kind[j] != kFluid) return;
    pair_F(acc, i, j, xij, W.grad_factor_r2(r2));
  }
  // The pair term given F (grad_i W_ij = F x_ij) for a neighbour in the continuum (FusedRatesPass).
  VARSPH_HD void pair_F(Real& acc, std::size_t i, std::size_t j, const Vec<D>& xij, Real F) const {
    acc += s.mass[j] * F * (s.v[i] - s.v[j]).dot(xij);
    if constexpr (Diffusion::enabled) {
      if constexpr (Diffusion::uses_pressure) {  // Riemann-solver dissipation (physics/riemann.hpp)
        if (s.kind[i] == kFluid && (s.kind[j] == kFluid || walls_in_continuum<M>))
          acc += diff.term_p(s.p[i], s.p[j], s.rho[i], volume[j], F, xij);
      } else if (s.kind[i] == kFluid && s.kind[j] == kFluid) {
        if constexpr (Diffusion::uses_gradient)  // delta-SPH with renormalised gradients (physics/delta_sph.hpp)
          acc += diff.term_g(i, j, s.rho[i], s.rho[j], volume[j], F, xij);
        else
          acc += diff.term(s.rho[i], s.rho[j], volume[j], F, xij);
      }
    }
  }
  VARSPH_HD void end(std::size_t i, Real acc) const { drho[i] = acc; }
};

// Summation density, seed eq. (8): rho_i = sum_j m_j W_ij (self term included).
template <int D, class Kernel, BoundaryModel M>
struct SummationDensityPass {
  const Kernel& W;
  const ParticleView<D>& s;
  Real* rho;
  VARSPH_HD bool active(std::size_t i) const { return s.kind[i] == kFluid || walls_evolve_density<M>; }
  VARSPH_HD Real begin(std::size_t i) const { return s.mass[i] * W.w_r2(Real(0)); }
  VARSPH_HD void pair(Real& acc, std::size_t, std::size_t j, const Vec<D>&, Real r2) const {
    if constexpr (!walls_in_continuum<M>)
      if (s.kind[j] != kFluid) return;
    acc += s.mass[j] * W.w_r2(r2);
  }
  VARSPH_HD void end(std::size_t i, Real acc) const { rho[i] = acc; }
};

// Acceleration of fluid particles: symmetric pressure term (seed eq. 38), the viscosity policy
// (Monaghan 1992 artificial viscosity, Morris 1997 laminar viscosity, both or none), the wall model
// (eq. 58 repulsive; dynamic / dummy walls as pressure particles; dummy + Chalk 2020 soft force) and
// the body acceleration (gravity eq. 59, ramped, plus physics.body_force).
template <int D, class Kernel, class Viscosity, BoundaryModel M>
struct AccelerationPass {
  static constexpr BoundaryModel model = M;
  const Kernel& W;
  const Viscosity& visc;
  const RepulsiveWall& wall;
  const ParticleView<D>& s;
  Vec<D> gravity;
  Vec<D>* acc_out;
  const SoftRepulsiveWall* soft = nullptr;  // used only when M == SoftRepulsive
  const Real* p_over_rho2 = nullptr;        // p / rho^2 per particle, computed once per pass (not per pair)
  const Vec<D>* vw = s.wall_v.empty() ? s.v.data() : s.wall_v.data();
  struct Acc {
    Vec<D> a;
    Real p_over_rho2;
  };
  VARSPH_HD bool active(std::size_t i) const { return s.kind[i] == kFluid; }
  VARSPH_HD Acc begin(std::size_t i) const { return {Vec<D>::Zero(), p_over_rho2[i]}; }
  VARSPH_HD void pair(Acc& acc, std::size_t i, std::size_t j, const Vec<D>& xij, Real r2) const {
    if constexpr (M == BoundaryModel::Repulsive) {
      if (s.kind[j] != kFluid) {
        acc.a += wall.factor(r2) * xij;  // eq. (58)
        return;
      }
    }
    pair_F(acc, i, j, xij, r2, W.grad_factor_r2(r2));  // grad_i W_ij = F x_ij
  }
  // The pair term given F for a fluid neighbour or a wall in the continuum (FusedRatesPass).
  VARSPH_HD void pair_F(Acc& acc, std::size_t i, std::size_t j, const Vec<D>& xij, Real r2, Real F) const {
    const bool j_fluid = s.kind[j] == kFluid;
    if constexpr (M == BoundaryModel::SoftRepulsive)
      if (!j_fluid) acc.a += soft->factor(r2) * xij;  // Chalk 2020
    Real coef = acc.p_over_rho2 + p_over_rho2[j];
    if constexpr (Viscosity::enabled) {
      // Artificial viscosity is a numerical dissipation of the fluid, not a wall friction: against an
      // extrapolated wall (dummy / mDBC: the view carries wall velocities and normals) it sees the
      // free-slip mirror image of the fluid (Adami 2012 eq. 22-23 with the tangential part kept): the
      // relative velocity 2 ((v_i - v_w) . n) n, which damps the approach and leaves the flow along the
      // wall free. (The no-slip mirror is for the laminar viscosity: with AV it acts as a friction of order
      // alpha c0 h that stalls the thin bore of a dam break: arrival at the far wall T = 3.0-3.3 instead of
      // 2.5 at H/dx = 25.) Dynamic walls keep DualSPHysics' rule: the wall's own velocity.
      if constexpr (Viscosity::artificial) {
        Vec<D> vij = s.v[i] - s.v[j];
        if (!j_fluid && !s.wall_v.empty() && !s.normal.empty())
          vij = (Real(2) * vij.dot(s.normal[j])) * s.normal[j];
        coef += visc.pi(vij.dot(xij), r2, s.rho[i], s.rho[j]);
      }
      if constexpr (Viscosity::laminar) {
        const Vec<D> vij = s.v[i] - ((M == BoundaryModel::Repulsive || j_fluid) ? s.v[j] : vw[j]);
        acc.a += visc.laminar_factor(s.mass[j], F, r2, s.rho[i], s.rho[j]) * vij;  // Morris 1997
      }
    }
    acc.a -= (s.mass[j] * coef * F) * xij;
  }
  VARSPH_HD void end(std::size_t i, const Acc& acc) const { acc_out[i] = acc.a + gravity; }
};

// Continuity and acceleration in one neighbour sweep (issue 9: "density and force passes fused where
// the scheme allows"): both at the same state, F computed once per pair. Per particle the two sums are
// accumulated in the same order as by the separate passes, so the results are bitwise identical.
template <int D, class DensityPass, class AccelPass>
struct FusedRatesPass {
  const DensityPass& dens;  // DensityRatePass (its model: Dynamic walls evolve their density)
  const AccelPass& accel;   // AccelerationPass (dynamic walls use the dummy-wall pressure pass)
  using AccelAcc = typename AccelPass::Acc;
  struct Acc {
    Real drho;
    AccelAcc a;
    bool fluid;
  };
  VARSPH_HD bool active(std::size_t i) const { return dens.active(i); }  // fluid, and dynamic walls
  VARSPH_HD Acc begin(std::size_t i) const {
    const bool fluid = accel.active(i);
    return {dens.begin(i), fluid ? accel.begin(i) : AccelAcc{Vec<D>::Zero(), Real(0)}, fluid};
  }
  VARSPH_HD void pair(Acc& acc, std::size_t i, std::size_t j, const Vec<D>& xij, Real r2) const {
    if constexpr (AccelPass::model == BoundaryModel::Repulsive) {
      if (dens.s.kind[j] != kFluid) {  // not in the continuum: only the eq. (58) force
        if (acc.fluid) acc.a.a += accel.wall.factor(r2) * xij;
        return;
      }
    }
    const Real F = dens.W.grad_factor_r2(r2);
    dens.pair_F(acc.drho, i, j, xij, F);
    if (acc.fluid) accel.pair_F(acc.a, i, j, xij, r2, F);
  }
  VARSPH_HD void end(std::size_t i, const Acc& acc) const {
    dens.end(i, acc.drho);
    if (acc.fluid) accel.end(i, acc.a);
  }
};

// Force of the fluid on boundary particles (probes: force and moment on a body). For boundary particle
// b: F_b = - sum_{fluid i} m_i a_ib, where a_ib is exactly the pair term the acceleration pass adds to
// fluid particle i for neighbour b (Newton's third law on the same pair terms: pressure, viscosity,
// repulsive wall). Gravity is not a pair term and is not included. Writes only boundary slots.
template <int D, class AccPass>
struct BoundaryReactionPass {
  const AccPass& acc_pass;
  const ParticleView<D>& s;
  Vec<D>* force;
  BoundaryFilter only = {};  // empty: every boundary particle; else those of the bodies it selects
  VARSPH_HD bool active(std::size_t b) const { return s.kind[b] != kFluid && only.selects(b); }
  VARSPH_HD Vec<D> begin(std::size_t) const { return Vec<D>::Zero(); }
  VARSPH_HD void pair(Vec<D>& f, std::size_t b, std::size_t i, const Vec<D>& x_bi, Real r2) const {
    if (s.kind[i] != kFluid) return;
    auto a = acc_pass.begin(i);
    acc_pass.pair(a, i, b, Vec<D>(-x_bi), r2);  // the term fluid i receives from b (x_ib = -x_bi)
    f -= s.mass[i] * a.a;
  }
  VARSPH_HD void end(std::size_t b, const Vec<D>& f) const { force[b] = f; }
};

// Monaghan (2000) artificial stress, added to existing accelerations (fluid-fluid pairs).
template <int D, class Kernel>
struct ArtificialStressPass {
  const Kernel& W;
  const ArtificialStress& as;
  const ParticleView<D>& s;
  Vec<D>* acc_out;
  VARSPH_HD bool active(std::size_t i) const { return s.kind[i] == kFluid; }
  VARSPH_HD Vec<D> begin(std::size_t) const { return Vec<D>::Zero(); }
  VARSPH_HD void pair(Vec<D>& acc, std::size_t i, std::size_t j, const Vec<D>& xij, Real r2) const {
    if (s.kind[j] != kFluid) return;
    const Real Rij = as.R(s.p[i], s.rho[i]) + as.R(s.p[j], s.rho[j]);
    if (Rij == Real(0)) return;
    acc -= (s.mass[j] * as.f_pow(W.w_r2(r2)) * Rij * W.grad_factor_r2(r2)) * xij;
  }
  VARSPH_HD void end(std::size_t i, const Vec<D>& acc) const { acc_out[i] += acc; }
};

// XSPH velocity correction, Monaghan (1989): dx_i/dt = v_i + eps sum_j m_j / rho_ij (v_j - v_i) W_ij,
// rho_ij = (rho_i + rho_j)/2, fluid neighbours. (The foundation notes write grad W; that is not a velocity.)
template <int D, class Kernel>
struct XsphPass {
  const Kernel& W;
  const ParticleView<D>& s;
  Real eps;
  Vec<D>* out;
  VARSPH_HD bool active(std::size_t i) const { return s.kind[i] == kFluid; }
  VARSPH_HD Vec<D> begin(std::size_t) const { return Vec<D>::Zero(); }
  VARSPH_HD void pair(Vec<D>& acc, std::size_t i, std::size_t j, const Vec<D>&, Real r2) const {
    if (s.kind[j] != kFluid) return;
    acc += (Real(2) * s.mass[j] / (s.rho[i] + s.rho[j]) * W.w_r2(r2)) * (s.v[j] - s.v[i]);
  }
  VARSPH_HD void end(std::size_t i, const Vec<D>& acc) const { out[i] = eps * acc; }
};

// Dummy-wall extrapolation of Adami, Hu & Adams (2012), eq. (27) and (22)-(23), on boundary particles w:
//   p_w = (sum_f p_f W_wf + (g - a_w) . sum_f rho_f x_wf W_wf) / sum_f W_wf,  rho_w = EOS^-1(p_w),
//   v~_w = sum_f v_f W_wf / sum_f W_wf;  no-slip: v_w = 2 v_wall - v~_w (Adami's rule);
//   free-slip: tangential part of v~_w - v_wall kept, normal part mirrored.
// a_w is the wall's prescribed acceleration (zero for walls at rest or in uniform motion).
template <int D, class Kernel>
struct AdamiWallPass {
  const Kernel& W;
  const ParticleView<D>& s;
  WallGeometry<D> geo;
  Vec<D> g;
  TaitEos eos;
  bool free_slip;
  Real* p_out;
  Real* rho_out;
  Vec<D>* vw_out;
  struct Acc {
    Real sw, spw;
    Vec<D> srx, sv;
  };
  VARSPH_HD bool active(std::size_t i) const { return s.kind[i] != kFluid; }
  VARSPH_HD Acc begin(std::size_t) const { return {Real(0), Real(0), Vec<D>::Zero(), Vec<D>::Zero()}; }
  VARSPH_HD void pair(Acc& acc, std::size_t, std::size_t j, const Vec<D>& xwf, Real r2) const {
    if (s.kind[j] != kFluid) return;
    const Real w = W.w_r2(r2);
    acc.sw += w;
    acc.spw += s.p[j] * w;
    acc.srx += (s.rho[j] * w) * xwf;
    acc.sv += w * s.v[j];
  }
  VARSPH_HD void end(std::size_t i, const Acc& acc) const {
    const Vec<D> vwall = s.v[i];
    if (acc.sw <= Real(0)) {
      p_out[i] = Real(0);
      rho_out[i] = eos.rho0;
      vw_out[i] = vwall;
      return;
    }
    const Real inv = Real(1) / acc.sw;
    const Real p = (acc.spw + (g - geo.accel(i)).dot(acc.srx)) * inv;  // Adami 2012 eq. (27)
    p_out[i] = p;
    rho_out[i] = p > -eos.B ? eos.density(p) : eos.rho0 * Real(1e-3);
    const Vec<D> u = acc.sv * inv - vwall;  // extrapolated fluid velocity relative to the wall
    if (!free_slip) {
      vw_out[i] = vwall - u;  // Adami 2012 eq. (22)-(23)
    } else {
      const Vec<D>& n = geo.normal[i];
      vw_out[i] = vwall + u - (Real(2) * u.dot(n)) * n;
    }
  }
};

}  // namespace varsph::physics
