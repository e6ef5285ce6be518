#pragma once
// Soft repulsive wall force of Chalk et al. (2020), foundation notes "A soft repulsive force":
//   F_i = sum_j 0.01 c^2 chi(r) f(gamma) x_ij / r^2,  chi = 1 - r / (1.5 dx) for r < 1.5 dx,
//   gamma = r / (0.75 h),  f = 2/3 (gamma <= 2/3), 2 gamma - 1.5 gamma^2 (<= 1), 0.5 (2 - gamma)^2 (< 2), 0.
// Acceleration on the fluid particle i from the boundary particle j (x_ij = x_i - x_j).
#include <cmath>

#include "core/real.hpp"

namespace varsph::physics {

struct SoftRepulsiveWall {
  Real scale, r_chi, r_chi2, inv_chi, inv_gh;
  SoftRepulsiveWall(Real coef, Real c0, Real dx, Real h)
      : scale(coef * c0 * c0), r_chi(Real(1.5) * dx), r_chi2(r_chi * r_chi), inv_chi(Real(1) / r_chi),
        inv_gh(Real(1) / (Real(0.75) * h)) {}
  // factor f with acceleration f * x_ij
  VARSPH_HD Real factor(Real r2) const {
    if (r2 >= r_chi2 || r2 <= Real(0)) return Real(0);
    const Real r = std::sqrt(r2);
    const Real chi = Real(1) - r * inv_chi;
    const Real g = r * inv_gh;
    Real f;
    if (g <= Real(2) / Real(3)) f = Real(2) / Real(3);
    else if (g <= Real(1)) f = Real(2) * g - Real(1.5) * g * g;
    else if (g < Real(2)) f = Real(0.5) * (Real(2) - g) * (Real(2) - g);
    else f = Real(0);
    return scale * chi * f / r2;
  }
};

}  // namespace varsph::physics
