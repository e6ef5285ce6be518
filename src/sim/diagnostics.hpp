#pragma once
// Global quantities over fluid particles, one row of diagnostics.csv (CONTRACT.md).
#include <array>
#include <string>

#include "sim/simulation.hpp"

namespace varsph {

struct Diagnostics {
  std::array<double, 3> momentum{};  // sum m v [kg m/s]
  double momentum_Q = 0;             // || (1/M) sum m v ||, M = number of fluid particles (seed, Fig. 5)
  double angular_momentum = 0;       // z component about the origin in 2D, |L| in 3D
  double kinetic_energy = 0;         // sum m |v|^2 / 2
  double potential_energy = 0;       // - sum m g . (x - domain.min)
  double internal_energy = 0;        // sum m pi(rho), d pi / d rho = p / rho^2 (seed eq. 16-17)
  double max_speed = 0;
  double density_error_max = 0;      // max |rho / rho0 - 1|
  // rigid bodies (issue 30; zero without them): sum M V, translational + rotational kinetic energy and
  // - sum M g . (X - domain.min), the same reference as the fluid's, so fluid + bodies is the system's ledger
  std::array<double, 3> bodies_momentum{};
  double bodies_kinetic_energy = 0;
  double bodies_potential_energy = 0;
};

template <int D>
Diagnostics compute_diagnostics(const Simulation<D>& sim);

// Tait internal energy per unit mass, pi(rho) = (B / rho0) [ (rho/rho0)^6 / 6 + rho0 / rho - 7/6 ].
double tait_internal_energy(double rho, double rho0, double B);

// First problem with the state, or an empty string: NaN, a fluid particle outside the domain, or a
// density error beyond health.max_density_error. Names the particle id and the value. The strict check
// tests use on runs that must stay clean; `varsph run` applies the health rules instead (sim/health.hpp).
template <int D>
std::string check_health(const Simulation<D>& sim);

}  // namespace varsph
