#pragma once
// Laminar (physical) viscosity of Morris, Fox & Zhu (1997), eq. (8) with mu = rho nu:
//   dv_i/dt += sum_j m_j (mu_i + mu_j) (x_ij . grad_i W_ij) / (rho_i rho_j (r^2 + 0.01 h^2)) v_ij.
// With grad_i W = F x_ij, x_ij . grad_i W = F r^2. Also the policy that combines it with Monaghan's term.
#include "core/real.hpp"
#include "physics/artificial_viscosity.hpp"

namespace varsph::physics {

struct LaminarViscosity {
  static constexpr bool enabled = true;
  static constexpr bool artificial = false, laminar = true;
  Real nu, eps_h2;
  LaminarViscosity(Real nu_, Real h) : nu(nu_), eps_h2(Real(0.01) * h * h) {}
  // factor k with dv_i/dt += k v_ij for one pair; F = grad factor, m_j mass of j
  VARSPH_HD Real laminar_factor(Real mj, Real F, Real r2, Real rho_i, Real rho_j) const {
    return mj * nu * (rho_i + rho_j) * F * r2 / (rho_i * rho_j * (r2 + eps_h2));  // Morris 1997 eq. (8)
  }
};

// Both terms: Monaghan's Pi_ij (shocks, stability) and Morris' physical viscosity.
struct ArtificialAndLaminarViscosity : ArtificialViscosity, LaminarViscosity {
  static constexpr bool enabled = true;
  static constexpr bool artificial = true, laminar = true;
  ArtificialAndLaminarViscosity(const ArtificialViscosity& a, const LaminarViscosity& l)
      : ArtificialViscosity(a), LaminarViscosity(l) {}
};

}  // namespace varsph::physics
