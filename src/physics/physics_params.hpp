#pragma once
// The physics a scene names, resolved once at setup into plain values (SI units).
#include "core/real.hpp"
#include "kernels/kernel_type.hpp"
#include "physics/shifting.hpp"
#include "physics/wall_mdbc_mode.hpp"

namespace varsph::physics {

enum class DensityMode { Continuity, Summation };
enum class BoundaryModel {
  Repulsive,      // seed paper eq. (58): boundary particles only push (Lennard-Jones form, Liu & Liu)
  Dynamic,        // dynamic boundary particles (Crespo et al. 2007): walls take part in continuity and pressure
  DummyAdami,     // dummy particles, pressure and velocity extrapolated from the fluid (Adami et al. 2012)
  SoftRepulsive,  // DummyAdami plus the soft repulsive force of Chalk et al. 2020 (foundation notes)
  Mdbc,           // modified dynamic boundary condition (English et al. 2022): ghost-node extrapolation
};
enum class WallSlip { NoSlip, FreeSlip };
enum class DensityDiffusion { None, Molteni, Fourtakas, Antuono };
enum class TensileFix { None, ArtificialStress };

template <int D>
struct PhysicsParams {
  kernels::KernelType kernel = kernels::KernelType::Gaussian;
  Real h = 0;               // smoothing length [m]
  Real kernel_l = 9.47;     // paper_literal kernel constant l (eq. 10)
  bool kernel_tabulated = true;  // W, F from a table in r^2 (kernels/tabulated.hpp) or exact
  Real rho0 = 1000;         // rest density [kg/m^3]
  Real c0 = 0;              // speed of sound [m/s]
  Real background_pressure = 0;  // p_b added by the equation of state [Pa]
  Real dx = 0;              // particle spacing [m] (soft repulsive force, artificial stress)
  Vec<D> gravity = Vec<D>::Zero();  // [m/s^2]
  DensityMode density = DensityMode::Continuity;
  bool artificial_viscosity = false;
  Real av_alpha = 0, av_beta = 0, av_eps = Real(0.01);
  BoundaryModel boundary = BoundaryModel::Repulsive;
  Real wall_D = 0, wall_r0 = 0;  // eq. (58): D [m^2/s^2], r0 [m]
  int wall_n1 = 12, wall_n2 = 4;

  // --- toolbox terms: each off unless the scene names it -------------------------------------
  WallSlip wall_slip = WallSlip::NoSlip;  // dummy_adami / soft_repulsive / mdbc wall velocity rule
  MdbcExtrapolation mdbc_extrapolation = MdbcExtrapolation::Gradient;
  Real soft_wall_coef = Real(0.01);       // Chalk 2020: force scale = coef c0^2
  bool laminar_viscosity = false;
  Real nu = 0;                            // kinematic viscosity [m^2/s] (Morris et al. 1997)
  Vec<D> body_force = Vec<D>::Zero();     // extra body acceleration [m/s^2], not ramped
  Real xsph_eps = 0;                      // XSPH epsilon in [0, 1]; 0 = off
  bool damping = false;
  Real damping_mu = 0, damping_until = 0;  // F = -mu v [1/s] while t < until [s]
  Real gravity_ramp = 0;                   // ramp duration [s]; 0 = off
  DensityDiffusion diffusion = DensityDiffusion::None;
  bool riemann = false;   // Zhang, Hu & Adams 2017 dissipation in place of artificial viscosity + delta-SPH
  Real riemann_eta = 3;   // slope of the low-dissipation limiter beta = min(eta u_a / c0, 1)
  Real diffusion_delta = Real(0.1);
  TensileFix tensile = TensileFix::None;
  Real as_eps = Real(0.2);  // Monaghan 2000 artificial stress epsilon
  Real as_n = Real(4);      // exponent n of f_ij = (W(r)/W(dx))^n
  ShiftingParams shifting;  // particle shifting (physics/shifting.hpp); off unless named
};

}  // namespace varsph::physics
