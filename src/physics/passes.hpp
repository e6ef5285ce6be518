#pragma once
// The pair passes, each a functor for for_each_particle_pairs, composed at compile time from the
// kernel, the viscosity term and the wall model a scene names: a term that is off is not compiled in.
#include <cstdint>

#include "core/real.hpp"
#include "physics/artificial_viscosity.hpp"
#include "physics/particle_view.hpp"
#include "physics/physics_params.hpp"
#include "physics/repulsive_wall.hpp"

namespace varsph::physics {

constexpr std::int32_t kFluid = 0;
constexpr std::int32_t kBoundary = 1;

// Does a boundary particle j count as a fluid-like neighbour (density, pressure)?
template <BoundaryModel M>
constexpr bool walls_in_continuum = (M == BoundaryModel::Dynamic);

// Continuity equation with the standard sign (PAPER-NOTES.md on seed eq. 67-68; Monaghan 1992):
// drho_i/dt = sum_j m_j (v_i - v_j) . grad_i W_ij
template <int D, class Kernel, BoundaryModel M>
struct DensityRatePass {
  const Kernel& W;
  const ParticleView<D>& s;
  Real* drho;
  bool active(std::size_t i) const { return s.kind[i] == kFluid || walls_in_continuum<M>; }
  Real begin(std::size_t) const { return Real(0); }
  void pair(Real& acc, std::size_t i, std::size_t j, const Vec<D>& xij, Real r2) const {
    if constexpr (!walls_in_continuum<M>)
      if (s.kind[j] != kFluid) return;
    acc += s.mass[j] * W.grad_factor_r2(r2) * (s.v[i] - s.v[j]).dot(xij);
  }
  void end(std::size_t i, Real acc) const { drho[i] = acc; }
};

// Summation density, seed eq. (8): rho_i = sum_j m_j W_ij (self term included).
template <int D, class Kernel, BoundaryModel M>
struct SummationDensityPass {
  const Kernel& W;
  const ParticleView<D>& s;
  Real* rho;
  bool active(std::size_t i) const { return s.kind[i] == kFluid || walls_in_continuum<M>; }
  Real begin(std::size_t i) const { return s.mass[i] * W.w_r2(Real(0)); }
  void pair(Real& acc, std::size_t, std::size_t j, const Vec<D>&, Real r2) const {
    if constexpr (!walls_in_continuum<M>)
      if (s.kind[j] != kFluid) return;
    acc += s.mass[j] * W.w_r2(r2);
  }
  void end(std::size_t i, Real acc) const { rho[i] = acc; }
};

// Acceleration of fluid particles: symmetric pressure term (seed eq. 38), artificial viscosity
// (Monaghan 1992, see artificial_viscosity.hpp), repulsive wall force (eq. 58) and gravity (eq. 59).
template <int D, class Kernel, class Viscosity, BoundaryModel M>
struct AccelerationPass {
  const Kernel& W;
  const Viscosity& visc;
  const RepulsiveWall& wall;
  const ParticleView<D>& s;
  Vec<D> gravity;
  Vec<D>* acc_out;
  const Real* p_over_rho2;  // p / rho^2 per particle, computed once per pass (not per pair)
  struct Acc {
    Vec<D> a;
    Real p_over_rho2;
  };
  bool active(std::size_t i) const { return s.kind[i] == kFluid; }
  Acc begin(std::size_t i) const { return {Vec<D>::Zero(), p_over_rho2[i]}; }
  void pair(Acc& acc, std::size_t i, std::size_t j, const Vec<D>& xij, Real r2) const {
    const bool j_fluid = s.kind[j] == kFluid;
    if (!j_fluid) {
      if constexpr (M == BoundaryModel::Repulsive) {
        acc.a += wall.factor(r2) * xij;  // eq. (58)
        return;
      }
    }
    const Real F = W.grad_factor_r2(r2);  // grad_i W_ij = F x_ij
    Real coef = acc.p_over_rho2 + p_over_rho2[j];
    if constexpr (Viscosity::enabled) coef += visc.pi((s.v[i] - s.v[j]).dot(xij), r2, s.rho[i], s.rho[j]);
    acc.a -= (s.mass[j] * coef * F) * xij;
  }
  void end(std::size_t i, const Acc& acc) const { acc_out[i] = acc.a + gravity; }
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
  bool active(std::size_t b) const { return s.kind[b] != kFluid; }
  Vec<D> begin(std::size_t) const { return Vec<D>::Zero(); }
  void pair(Vec<D>& f, std::size_t b, std::size_t i, const Vec<D>& x_bi, Real r2) const {
    if (s.kind[i] != kFluid) return;
    auto a = acc_pass.begin(i);
    acc_pass.pair(a, i, b, Vec<D>(-x_bi), r2);  // the term fluid i receives from b (x_ib = -x_bi)
    f -= s.mass[i] * a.a;
  }
  void end(std::size_t b, const Vec<D>& f) const { force[b] = f; }
};

}  // namespace varsph::physics
