#pragma once
// Turns the scene's bodies into particles (lattice fills, tank walls, spheres, explicit points, meshes).
#include <cstdint>
#include <vector>

#include "core/real.hpp"
#include "scene/scene.hpp"

namespace varsph {

template <int D>
struct InitialParticles {
  std::vector<Vec<D>> x, v, normal;
  std::vector<Real> rho, mass;
  // boundary particles: distance to the fluid-wall interface along `normal` [m] (mDBC ghost nodes)
  std::vector<Real> wall_distance;
  std::vector<std::int32_t> kind;
  std::vector<int> body;  // index of the body each particle came from
  std::size_t count(std::int32_t k) const;
};

// `B` and `rho0` give hydrostatic initial densities; `gravity` their direction.
template <int D>
InitialParticles<D> build_particles(const scene::Scene& s, double B);

}  // namespace varsph
