#pragma once
// What the physics passes read: a configuration (positions), the velocities to use for viscosity and
// continuity, densities, pressures, masses and kinds. The integrators point these at the current state
// or at generalized-midpoint configurations (seed eq. 20-21, 30-31).
#include <cstdint>
#include <span>

#include "core/real.hpp"

namespace varsph::physics {

template <int D>
struct ParticleView {
  std::span<const Vec<D>> x;
  std::span<const Vec<D>> v;
  std::span<const Real> rho;
  std::span<const Real> p;
  std::span<const Real> mass;
  std::span<const std::int32_t> kind;
  // Velocities boundary particles show to viscosity (dummy/Adami walls: 2 v_wall - v_extrapolated);
  // empty = use v (walls at their prescribed velocity).
  std::span<const Vec<D>> wall_v = {};
  // Unit wall normals into the fluid (boundary particles), for the wall part of artificial viscosity
  // of extrapolated walls; empty = not used.
  std::span<const Vec<D>> normal = {};
  VARSPH_HD std::size_t size() const { return x.size(); }
};

}  // namespace varsph::physics
