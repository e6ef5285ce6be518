#pragma once
// Damping zone: wave absorption at the end of a flume by relaxing the fluid's velocity towards zero, as in
// DualSPHysics (Altomare et al. 2017, Coastal Eng. 127, "Long-crested wave generation and absorption for
// SPH-based DualSPHysics model", section 2.4): after each step,
//   v <- v max(0, 1 - dt beta f(s)),   s = (x - x_from) . n / L  (n = (x_to - x_from) / L, L = |x_to - x_from|)
//   f = s^2 (quadratic, the paper's profile) or s (linear) for 0 < s <= 1, 1 beyond `to`, 0 before `from`.
// beta [1/s] is the largest relaxation rate (DualSPHysics' redumax, 10 by default). On only when the scene
// names physics.damping_zone; per particle, each writing its own slot (bitwise the same on any thread count
// and rank count).
#include <algorithm>

#include "core/host_device.hpp"
#include "core/real.hpp"

namespace varsph::physics {

template <int D>
struct DampingZone {
  Vec<D> from = Vec<D>::Zero();
  Vec<D> normal = Vec<D>::Zero();  // unit, from -> to
  Real length = 1, beta = 10;
  bool quadratic = true;

  // The factor that multiplies a velocity at x after a step of dt.
  VARSPH_HD Real factor(const Vec<D>& x, Real dt) const {
    const Real s = (x - from).dot(normal) / length;
    if (!(s > 0)) return Real(1);
    const Real sc = s < Real(1) ? s : Real(1);
    const Real f = quadratic ? sc * sc : sc;
    const Real r = Real(1) - dt * beta * f;
    return r > Real(0) ? r : Real(0);
  }
};

}  // namespace varsph::physics
