#pragma once
// Artificial stress against the tensile instability, Monaghan (2000), in the isotropic fluid form of
// Gray, Monaghan & Swift (2001): dv_i/dt += - sum_j m_j f_ij^n (R_i + R_j) grad_i W_ij,
//   f_ij = W(r_ij) / W(dx),  R_i = eps |p_i| / rho_i^2 if p_i < 0 else 0  (n = 4, eps = 0.2 usual).
#include <cmath>

#include "core/real.hpp"

namespace varsph::physics {

struct ArtificialStress {
  Real eps, inv_w_dx;
  int n;
  ArtificialStress(Real eps_, Real w_dx, Real n_) : eps(eps_), inv_w_dx(Real(1) / w_dx), n(int(n_)) {}
  Real R(Real p, Real rho) const { return p < Real(0) ? -eps * p / (rho * rho) : Real(0); }
  Real f_pow(Real w) const {
    const Real f = w * inv_w_dx;
    if (n == 4) { const Real f2 = f * f; return f2 * f2; }
    return std::pow(f, Real(n));
  }
};

}  // namespace varsph::physics
