#pragma once
// What the wall models that extrapolate from the fluid (Adami dummy walls, mDBC) read about each
// boundary particle besides the particle view: its unit normal into the fluid, its distance to the
// fluid-wall interface along that normal (the mirror/ghost node of mDBC sits at twice that distance),
// and the wall's prescribed acceleration (Adami 2012 eq. 27; the mDBC pressure clone).
#include "core/real.hpp"

namespace varsph::physics {

template <int D>
struct WallGeometry {
  const Vec<D>* normal = nullptr;        // unit normal from the wall into the fluid (zero: unknown)
  const Real* distance = nullptr;        // distance to the interface along the normal [m] (mDBC only)
  const Vec<D>* acceleration = nullptr;  // a_w [m/s^2]; null: walls at rest or in uniform motion
  VARSPH_HD Vec<D> accel(std::size_t i) const { return acceleration ? acceleration[i] : Vec<D>::Zero(); }
};

}  // namespace varsph::physics
