#pragma once
// Density diffusion (delta-SPH) added to the continuity equation, fluid-fluid pairs only:
//   D_i = delta h c0 sum_j V_j psi_ij . grad_i W_ij,  psi_ij = 2 (rho_j - rho_i) x_ji / r^2
// (Molteni & Colagrossi 2009). With grad_i W = F x_ij and x_ji = -x_ij: D_i = -2 delta h c0 sum_j V_j (rho_j - rho_i) F.
// Fourtakas et al. (2019) subtract the hydrostatic part of the density difference:
//   rho_j - rho_i -> rho_j - rho_i - rho0 [(1 + rho0 g . x_ji / B)^(1/7) - 1]  (Tait, gamma = 7; series to 3rd order).
#include <cmath>

#include "core/real.hpp"

namespace varsph::physics {

struct NoDensityDiffusion {
  static constexpr bool enabled = false;
  static constexpr bool uses_pressure = false;
  static constexpr bool uses_gradient = false;
};

struct MolteniDiffusion {
  static constexpr bool enabled = true;
  static constexpr bool uses_pressure = false;
  static constexpr bool uses_gradient = false;
  Real coef;  // 2 delta h c0
  MolteniDiffusion(Real delta, Real h, Real c0) : coef(Real(2) * delta * h * c0) {}
  // Vj = m_j / rho_j, computed once per particle by the pass
  template <int D>
  VARSPH_HD Real term(Real rho_i, Real rho_j, Real Vj, Real F, const Vec<D>&) const {
    return -coef * (rho_j - rho_i) * F * Vj;  // Molteni & Colagrossi 2009
  }
};

template <int D>
struct FourtakasDiffusion {
  static constexpr bool enabled = true;
  static constexpr bool uses_pressure = false;
  static constexpr bool uses_gradient = false;
  Real coef, rho0, rho0_over_B;
  Vec<D> g;
  FourtakasDiffusion(Real delta, Real h, Real c0, Real rho0_, const Vec<D>& g_)
      : coef(Real(2) * delta * h * c0), rho0(rho0_), rho0_over_B(Real(7) / (c0 * c0)), g(g_) {}
  template <int DD>
  VARSPH_HD Real term(Real rho_i, Real rho_j, Real Vj, Real F, const Vec<DD>& xij) const {
    // hydrostatic density difference rho_j^H - rho_i^H for p_j^H - p_i^H = rho0 g . (x_j - x_i)
    const Real dp_over_B = rho0_over_B * (-g.dot(xij));  // rho0 g.x_ji / B with B = rho0 c0^2 / 7
    // (1 + a)^(1/7) - 1 by its series to a^3 (|a| = 7 g r / c0^2 << 1 within a kernel support; a^4 term < 1e-8 a)
    const Real a = dp_over_B;
    const Real drho_h = rho0 * a * (Real(1) / Real(7) + a * (Real(-3) / Real(49) + a * (Real(13) / Real(343))));
    return -coef * (rho_j - rho_i - drho_h) * F * Vj;  // Fourtakas et al. 2019
  }
};

}  // namespace varsph::physics
