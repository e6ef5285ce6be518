#pragma once
// Repulsive boundary force of the seed paper, eq. (58), in Liu & Liu's form with x/r^2 (PAPER-NOTES.md:
// with D in m^2/s^2 only x/r^2 gives an acceleration): for r < r0,
//   Gamma = D [(r0/r)^n1 - (r0/r)^n2] x_ig / r^2,   n1 = 12, n2 = 4 (powers by multiplication).
#include <cmath>

#include "core/real.hpp"

namespace varsph::physics {

struct RepulsiveWall {
  Real D, r0, r0_2;
  int n1, n2;
  RepulsiveWall(Real D_, Real r0_, int n1_, int n2_) : D(D_), r0(r0_), r0_2(r0_ * r0_), n1(n1_), n2(n2_) {}
  // factor f with acceleration f * x_ig (x_ig = x_i - x_g)
  VARSPH_HD Real factor(Real r2) const {
    if (r2 >= r0_2 || r2 <= Real(0)) return Real(0);
    const Real s2 = r0_2 / r2;  // (r0/r)^2
    Real p1, p2;
    if (n1 == 12 && n2 == 4) {
      p2 = s2 * s2;
      p1 = p2 * p2 * p2;
    } else {
      const Real s = std::sqrt(s2);
      p1 = std::pow(s, Real(n1));
      p2 = std::pow(s, Real(n2));
    }
    return D * (p1 - p2) / r2;
  }
};

}  // namespace varsph::physics
