#pragma once
// Rates of change of the fluid state, one virtual call per pass (never per pair). The concrete class
// is instantiated for the scene's kernel, viscosity and wall model by make_rates().
#include <memory>

#include "neighbors/neighbor_grid.hpp"
#include "physics/particle_view.hpp"
#include "physics/physics_params.hpp"

namespace varsph::physics {

template <int D>
class Rates {
 public:
  virtual ~Rates() = default;
  // drho/dt by continuity at configuration s.x with velocities s.v (standard sign).
  virtual void density_rate(const NeighborGrid<D>& grid, const ParticleView<D>& s, Real* drho) const = 0;
  // rho by summation, seed eq. (8).
  virtual void summation_density(const NeighborGrid<D>& grid, const ParticleView<D>& s, Real* rho) const = 0;
  // accelerations of fluid particles (boundary particles untouched).
  virtual void acceleration(const NeighborGrid<D>& grid, const ParticleView<D>& s, Vec<D>* a) const = 0;
  // force of the fluid on every boundary particle (BoundaryReactionPass; fluid slots untouched) [N]
  virtual void boundary_reaction(const NeighborGrid<D>& grid, const ParticleView<D>& s, Vec<D>* force) const = 0;
  virtual Real support() const = 0;
  virtual Real kernel_w(Real r) const = 0;  // W(r), for probes and tests
};

template <int D>
std::unique_ptr<Rates<D>> make_rates(const PhysicsParams<D>& params);

}  // namespace varsph::physics
