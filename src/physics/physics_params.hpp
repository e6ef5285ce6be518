#pragma once
// The physics a scene names, resolved once at setup into plain values (SI units).
#include "core/real.hpp"
#include "kernels/kernel_type.hpp"

namespace varsph::physics {

enum class DensityMode { Continuity, Summation };
enum class BoundaryModel {
  Repulsive,  // seed paper eq. (58): boundary particles only push (Liu & Liu)
  Dynamic,    // dynamic boundary particles (Crespo et al. 2007): walls take part in continuity and pressure
};

template <int D>
struct PhysicsParams {
  kernels::KernelType kernel = kernels::KernelType::Gaussian;
  Real h = 0;               // smoothing length [m]
  Real kernel_l = 9.47;     // paper_literal kernel constant l (eq. 10)
  bool kernel_tabulated = true;  // W, F from a table in r^2 (kernels/tabulated.hpp) or exact
  Real rho0 = 1000;         // rest density [kg/m^3]
  Real c0 = 0;              // speed of sound [m/s]
  Vec<D> gravity = Vec<D>::Zero();  // [m/s^2]
  DensityMode density = DensityMode::Continuity;
  bool artificial_viscosity = false;
  Real av_alpha = 0, av_beta = 0, av_eps = Real(0.01);
  BoundaryModel boundary = BoundaryModel::Repulsive;
  Real wall_D = 0, wall_r0 = 0;  // eq. (58): D [m^2/s^2], r0 [m]
  int wall_n1 = 12, wall_n2 = 4;
};

}  // namespace varsph::physics
