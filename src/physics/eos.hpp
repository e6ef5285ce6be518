#pragma once
// Tait equation of state, seed paper eq. (11): p = B [(rho/rho0)^7 - 1] + p_b, B = c0^2 rho0 / 7, with an
// optional background pressure p_b (default 0; periodic shear flows need it against tensile clumping).
#include "core/real.hpp"

namespace varsph::physics {

struct TaitEos {
  Real rho0, B, inv_rho0, pb;
  TaitEos(Real rho0_, Real c0, Real background = Real(0))
      : rho0(rho0_), B(c0 * c0 * rho0_ / Real(7)), inv_rho0(Real(1) / rho0_), pb(background) {}
  VARSPH_HD Real pressure(Real rho) const {
    const Real r = rho * inv_rho0;
    const Real r2 = r * r;
    const Real r7 = r2 * r2 * r2 * r;  // (rho/rho0)^7 by multiplications
    return B * (r7 - Real(1)) + pb;
  }
  // inverse, for hydrostatic initial densities: rho = rho0 (1 + p/B)^(1/7)
  VARSPH_HD Real density(Real p) const;
};

}  // namespace varsph::physics

#include <cmath>
VARSPH_HD inline varsph::Real varsph::physics::TaitEos::density(Real p) const {
  return rho0 * std::pow(Real(1) + (p - pb) / B, Real(1) / Real(7));
}
