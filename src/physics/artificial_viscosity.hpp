#pragma once
// Monaghan (1992) artificial viscosity in its standard form (foundation notes "Artificial viscosity -
// standard approach"; PAPER-NOTES.md on the sign typo of seed eq. (55)):
//   Pi_ij = (-alpha c phi + beta phi^2) / rho_ij for v_ij . x_ij < 0, else 0,
//   phi = h v_ij . x_ij / (r^2 + eps h^2), added to the momentum equation as - m_j Pi_ij grad_i W.
#include "core/real.hpp"

namespace varsph::physics {

struct NoViscosity {
  static constexpr bool enabled = false;
  static constexpr bool artificial = false, laminar = false;
};

struct ArtificialViscosity {
  static constexpr bool enabled = true;
  static constexpr bool artificial = true, laminar = false;
  Real alpha, beta, c0, h, eps_h2;
  ArtificialViscosity(Real alpha_, Real beta_, Real c0_, Real h_, Real eps = Real(0.01))
      : alpha(alpha_), beta(beta_), c0(c0_), h(h_), eps_h2(eps * h_ * h_) {}
  // Pi_ij (>= 0 for approaching pairs); vx = v_ij . x_ij
  VARSPH_HD Real pi(Real vx, Real r2, Real rho_i, Real rho_j) const {
    if (vx >= Real(0)) return Real(0);
    const Real phi = h * vx / (r2 + eps_h2);
    return (-alpha * c0 * phi + beta * phi * phi) * Real(2) / (rho_i + rho_j);
  }
};

}  // namespace varsph::physics
