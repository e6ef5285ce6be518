#pragma once
// The physics passes of physics/passes.hpp as the device loops build them: each maker holds the values
// a pass refers to (kernel table, terms, the particle view of device arrays) and, inside the thread,
// builds the pass over its own copy and hands it to the loop (PairBody). The passes and terms are the
// host's own functors; only where their inputs live differs.
#include "integrators/variational_passes.hpp"
#include "kernels/tabulated.hpp"
#include "physics/passes.hpp"

namespace varsph::exec {

template <int D>
using DeviceKernel = kernels::TableView<D>;

template <int D, class Visc, physics::BoundaryModel M>
struct AccelerationMaker {
  using Pass = physics::AccelerationPass<D, DeviceKernel<D>, Visc, M>;
  DeviceKernel<D> W;
  Visc visc;
  physics::RepulsiveWall wall;
  physics::SoftRepulsiveWall soft;
  physics::ParticleView<D> s;
  Vec<D> gravity;
  Vec<D>* out;
  const Real* p_over_rho2;
  template <class F>
  VARSPH_HD void with(F&& f) const {
    const Pass pass{W, visc, wall, s, gravity, out, &soft, p_over_rho2};
    f(pass);
  }
};

template <int D, physics::BoundaryModel M, class Diff>
struct DensityRateMaker {
  using Pass = physics::DensityRatePass<D, DeviceKernel<D>, M, Diff>;
  DeviceKernel<D> W;
  physics::ParticleView<D> s;
  Real* drho;
  Diff diff;
  const Real* volume;
  template <class F>
  VARSPH_HD void with(F&& f) const {
    const Pass pass{W, s, drho, diff, volume};
    f(pass);
  }
};

template <int D, physics::BoundaryModel M>
struct SummationMaker {
  DeviceKernel<D> W;
  physics::ParticleView<D> s;
  Real* rho;
  template <class F>
  VARSPH_HD void with(F&& f) const {
    const physics::SummationDensityPass<D, DeviceKernel<D>, M> pass{W, s, rho};
    f(pass);
  }
};

// continuity (wall model MD) and acceleration (MA) in one sweep: physics::FusedRatesPass
template <int D, class Visc, physics::BoundaryModel MD, physics::BoundaryModel MA, class Diff>
struct FusedMaker {
  using Dens = physics::DensityRatePass<D, DeviceKernel<D>, MD, Diff>;
  using Accel = physics::AccelerationPass<D, DeviceKernel<D>, Visc, MA>;
  DeviceKernel<D> W;
  Visc visc;
  physics::RepulsiveWall wall;
  physics::SoftRepulsiveWall soft;
  physics::ParticleView<D> s;
  Vec<D> gravity;
  Real* drho;
  Vec<D>* a;
  Diff diff;
  const Real* volume;
  const Real* p_over_rho2;
  template <class F>
  VARSPH_HD void with(F&& f) const {
    const Dens dens{W, s, drho, diff, volume};
    const Accel accel{W, visc, wall, s, gravity, a, &soft, p_over_rho2};
    const physics::FusedRatesPass<D, Dens, Accel> pass{dens, accel};
    f(pass);
  }
};

// the renormalised density gradients of Antuono et al. 2010's delta-SPH (physics/delta_sph.hpp)
template <int D>
struct DensityGradientMaker {
  DeviceKernel<D> W;
  physics::ParticleView<D> s;
  const Real* volume;
  Vec<D>* out;
  template <class F>
  VARSPH_HD void with(F&& f) const {
    const physics::RenormalisedDensityGradientPass<D, DeviceKernel<D>> pass{W, s, volume, out};
    f(pass);
  }
};

// dummy walls (Adami et al. 2012): wall pressure, density and viscous velocity from the fluid
template <int D>
struct AdamiWallMaker {
  DeviceKernel<D> W;
  physics::ParticleView<D> s;
  physics::WallGeometry<D> geo;  // normals (a_w: none, moving walls are refused on the device)
  Vec<D> g;
  physics::TaitEos eos;
  bool free_slip;
  Real* p;
  Real* rho;
  Vec<D>* wall_v;
  template <class F>
  VARSPH_HD void with(F&& f) const {
    const physics::AdamiWallPass<D, DeviceKernel<D>> pass{W, s, geo, g, eos, free_slip, p, rho, wall_v};
    f(pass);
  }
};

// Gamma_k of the variational integrator (eq. 58 alone)
template <int D>
struct WallOnlyMaker {
  physics::RepulsiveWall wall;
  physics::ParticleView<D> s;
  Vec<D>* out;
  Real support;
  template <class F>
  VARSPH_HD void with(F&& f) const {
    const WallOnlyPass<D> pass{wall, s, out, support};
    f(pass);
  }
};

}  // namespace varsph::exec
