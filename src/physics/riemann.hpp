#pragma once
// Low-dissipation Riemann-solver terms of Zhang, Hu & Adams (2017), "A weakly compressible SPH method
// based on a low-dissipation Riemann solver", J. Comput. Phys. 335:605-620, linearised with the
// reference impedance rho0 c0 (as SPHinXsys does). For a pair, along the line of centres (L = i, R = j):
//   approach speed  u_a = U_L - U_R = -v_ij . x_ij / r
//   P*  = (p_i + p_j)/2 + (1/2) rho0 c0 beta u_a,  beta = min(eta max(u_a, 0) / c0, 1)   (eq. 14, 23)
//   U*  = (U_L + U_R)/2 + (p_i - p_j) / (2 rho0 c0)
// Momentum: dv_i/dt = -2 sum_j m_j P* / (rho_i rho_j) grad_i W_ij. Here the pressure part keeps the
// symmetric form of seed eq. (38) (equal to (p_i + p_j)/(rho_i rho_j) to O((rho - rho0)^2)) and the
// dissipative part enters like an artificial viscosity, Pi_ij = rho0 c0 beta u_a / (rho_i rho_j): zero
// for separating pairs, quadratic in u_a for weak compressions (the "low dissipation"), linear in
// shocks. Continuity: dissipation from U*, drho_i/dt += rho_i sum_j V_j (p_i - p_j) / (rho0 c0) dW/dr
// (always on, as in the paper and SPHinXsys), a pressure-driven density diffusion on fluid pairs.
#include <algorithm>
#include <cmath>

#include "core/real.hpp"
#include "physics/laminar_viscosity.hpp"

namespace varsph::physics {

struct RiemannDissipation {
  static constexpr bool enabled = true;
  static constexpr bool artificial = true, laminar = false;
  Real rho0c0, eta_over_c0;
  RiemannDissipation(Real rho0, Real c0, Real eta) : rho0c0(rho0 * c0), eta_over_c0(eta / c0) {}
  // Pi_ij for the momentum equation; vx = v_ij . x_ij
  VARSPH_HD Real pi(Real vx, Real r2, Real rho_i, Real rho_j) const {
    if (vx >= Real(0) || r2 <= Real(0)) return Real(0);
    const Real ua = -vx / std::sqrt(r2);
    const Real beta = std::min(eta_over_c0 * ua, Real(1));  // low-dissipation limiter (eq. 23)
    return rho0c0 * beta * ua / (rho_i * rho_j);
  }
};

struct RiemannAndLaminarViscosity : RiemannDissipation, LaminarViscosity {
  static constexpr bool enabled = true;
  static constexpr bool artificial = true, laminar = true;
  RiemannAndLaminarViscosity(const RiemannDissipation& r, const LaminarViscosity& l)
      : RiemannDissipation(r), LaminarViscosity(l) {}
};

// The continuity part, in the density-diffusion slot of the continuity pass. The pressure jump is taken
// without its hydrostatic part, p_i - p_j - rho0 g . x_ij (as Fourtakas et al. 2019 do for delta-SPH):
// the term is a discrete Laplacian, zero for a linear field over a full support, but where the support is
// cut (free surface) it would diffuse the hydrostatic stratification itself (measured: floor pressure
// 15 % low in a tank at rest). Walls in the continuum take part with their extrapolated pressures.
template <int D>
struct RiemannDiffusion {
  static constexpr bool enabled = true;
  static constexpr bool uses_pressure = true;
  static constexpr bool uses_gradient = false;
  static constexpr bool with_walls = true;
  Real inv_rho0c0, rho0;
  Vec<D> g;
  RiemannDiffusion(Real rho0_, Real c0, const Vec<D>& g_) : inv_rho0c0(Real(1) / (rho0_ * c0)), rho0(rho0_), g(g_) {}
  // rho_i V_j (p_i - p_j - rho0 g . x_ij) / (rho0 c0) dW/dr with dW/dr = F r
  VARSPH_HD Real term_p(Real p_i, Real p_j, Real rho_i, Real Vj, Real F, const Vec<D>& xij) const {
    return rho_i * Vj * (p_i - p_j - rho0 * g.dot(xij)) * inv_rho0c0 * F * xij.norm();
  }
};

}  // namespace varsph::physics
