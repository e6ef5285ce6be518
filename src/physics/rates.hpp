#pragma once
// Rates of change of the fluid state, one virtual call per pass (never per pair). The concrete class
// is instantiated for the scene's kernel; the viscosity, wall and density-diffusion policies are picked
// once at construction (make_rates()), each combination a separately compiled pass.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>

#include "neighbors/neighbor_grid.hpp"
#include "physics/boundary_filter.hpp"
#include "physics/particle_view.hpp"
#include "physics/physics_params.hpp"
#include "physics/wall_geometry.hpp"

namespace varsph::physics {

template <int D>
class Rates {
 public:
  virtual ~Rates() = default;
  // drho/dt by continuity at configuration s.x with velocities s.v (standard sign) [+ density diffusion].
  virtual void density_rate(const NeighborGrid<D>& grid, const ParticleView<D>& s, Real* drho) const = 0;
  // rho by summation, seed eq. (8).
  virtual void summation_density(const NeighborGrid<D>& grid, const ParticleView<D>& s, Real* rho) const = 0;
  // accelerations of fluid particles (boundary particles untouched), with the named optional terms
  // (artificial stress, damping) applied.
  virtual void acceleration(const NeighborGrid<D>& grid, const ParticleView<D>& s, Vec<D>* a) const = 0;
  // density_rate and acceleration at the same state in one neighbour sweep where this build compiles
  // the fused pass (tabulated kernels, the default); otherwise the two passes. Results are identical.
  virtual void density_rate_and_acceleration(const NeighborGrid<D>& grid, const ParticleView<D>& s, Real* drho,
                                             Vec<D>* a) const {
    density_rate(grid, s, drho);
    acceleration(grid, s, a);
  }
  virtual bool fused() const { return false; }  // true when density_rate_and_acceleration is one sweep
  // True when every pass but shifting and boundary_reaction is a gather over the grid's blocks and
  // writes nothing but their particles' slots: a pass over a grid holding some of the blocks then
  // computes for their particles what the pass over all blocks does, so a pass may run as two sweeps
  // over complementary sets of blocks (parallel/halo_rates.hpp overlaps the halo exchange that way).
  // False when a pass also does per-particle work that must run once (damping) or reads what another
  // sweep of the same call wrote for the neighbours (Antuono's density gradients), or mDBC.
  virtual bool splits_by_blocks() const { return false; }
  // instruction set of the vectorised pair sweep in use where it covers the scene's terms ("scalar": none)
  virtual const char* simd() const { return "scalar"; }
  // force of the fluid on every boundary particle (BoundaryReactionPass; fluid slots untouched) [N]
  // `only`: the boundary particles to compute (rigid bodies); default every one.
  virtual void boundary_reaction(const NeighborGrid<D>& grid, const ParticleView<D>& s, Vec<D>* force,
                                 BoundaryFilter only = {}) const = 0;
  virtual Real support() const = 0;
  virtual Real kernel_w(Real r) const = 0;  // W(r), for probes and tests

  // --- time-dependent and optional parts (toolbox) ---------------------------------------------
  // Sets the time for the gravity ramp and the damping window (Simulation::advance, once per step).
  virtual void set_time(double) {}
  // Body acceleration in use now: ramped gravity + physics.body_force [m/s^2].
  virtual Vec<D> body_acceleration() const = 0;
  // Walls extrapolated from the fluid (Adami dummy walls, mDBC): writes p, rho and the viscous wall
  // velocity of boundary particles. Returns false (and writes nothing) for the other wall models.
  virtual bool update_walls(const NeighborGrid<D>&, const ParticleView<D>&, const WallGeometry<D>&,
                            Real* /*p*/, Real* /*rho*/, Vec<D>* /*wall_v*/) const {
    return false;
  }
  // XSPH velocity correction (zero-cost when physics.xsph is not named: xsph_enabled() false).
  virtual bool xsph_enabled() const { return false; }
  virtual void xsph(const NeighborGrid<D>&, const ParticleView<D>&, Vec<D>* /*out*/) const {}
  // Particle shifting displacement dr of fluid particles for a step of length dt (physics.shifting;
  // physics/shifting.hpp). Off unless named: shifting_enabled() false, shifting() never called.
  virtual bool shifting_enabled() const { return false; }
  virtual void shifting(const NeighborGrid<D>&, const ParticleView<D>&, Real /*dt*/, Vec<D>* /*out*/) const {}

  // A maximum over this process's particles made global (the shifting pass's "max" speed): the identity
  // in one process; a distributed run (parallel/halo_rates.hpp) sets the maximum over all ranks.
  std::function<Real(Real)> global_max = [](Real v) { return v; };
  // Copies the owners' values of a per-particle scratch array (count elements of `bytes`, owned then
  // ghosts) into the ghosts: null in one process; a distributed run (parallel/halo_rates.hpp) sets the
  // halo exchange. Called only by a pass that reads a neighbour-derived quantity a ghost cannot compute
  // itself (its neighbourhood is cut by the halo): Antuono's renormalised density gradients.
  std::function<void(void* data, std::size_t bytes, std::size_t count)> refresh_ghosts;
};

template <int D>
std::unique_ptr<Rates<D>> make_rates(const PhysicsParams<D>& params);

}  // namespace varsph::physics
