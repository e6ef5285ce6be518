#pragma once
// The pass the variational integrator adds to the scene's rates: the repulsive boundary force alone,
// seed eq. (58) (x/r^2 form, see repulsive_wall.hpp), on fluid particles from boundary particles, at the
// configuration of the view (q_k): Gamma_k of eq. (64)-(65). Shared by the host integrator
// (variational.cpp) and the device one (src/exec/).
#include "physics/particle_view.hpp"
#include "physics/passes.hpp"
#include "physics/repulsive_wall.hpp"

namespace varsph {

template <int D>
struct WallOnlyPass {
  const physics::RepulsiveWall& wall;
  const physics::ParticleView<D>& s;
  Vec<D>* out;
  Real support;  // read by the vectorised sweep's candidate test (physics/simd/)
  VARSPH_HD bool active(std::size_t i) const { return s.kind[i] == physics::kFluid; }
  VARSPH_HD Vec<D> begin(std::size_t) const { return Vec<D>::Zero(); }
  VARSPH_HD void pair(Vec<D>& acc, std::size_t, std::size_t j, const Vec<D>& xij, Real r2) const {
    if (s.kind[j] != physics::kFluid) acc += wall.factor(r2) * xij;  // eq. (58)
  }
  VARSPH_HD void end(std::size_t i, const Vec<D>& acc) const { out[i] = acc; }
};

}  // namespace varsph
