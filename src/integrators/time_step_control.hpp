#pragma once
// CFL-adaptive time step: the three classical limits, each with its own coefficient (scene keys
// integrator.cfl_criteria.{acoustic, force, viscous}, defaults integrator.cfl, integrator.cfl, 0.125):
//   acoustic  C_a h / (c0 + v_max)          (Monaghan 1992; foundation notes "CFL", with c0 added)
//   force     C_f sqrt(h / a_max)           (Monaghan 1992)
//   viscous   C_v h^2 / nu                  (Morris et al. 1997); nu is the kinematic viscosity of the
//             scene's viscous terms: Monaghan's artificial viscosity acts as nu = alpha c0 h / (2 (d + 2))
//             (Monaghan 2005, eq. 4.14 with the standard definitions); infinite without viscosity.
// dt = min(acoustic, force, viscous). v_max and a_max are over fluid particles; a is the last
// acceleration evaluated by the integrator (zero before the first step).
#include <limits>

#include "core/real.hpp"

namespace varsph {

template <int D>
class Simulation;

struct CflLimits {
  double acoustic = std::numeric_limits<double>::infinity();  // [s]
  double force = std::numeric_limits<double>::infinity();     // [s]
  double viscous = std::numeric_limits<double>::infinity();   // [s]
  double v_max = 0, a_max = 0, nu = 0;                        // [m/s], [m/s^2], [m^2/s]
  double dt() const;                                          // the smallest of the three [s]
  const char* binding() const;                                // which limit sets dt
};

// Kinematic viscosity the viscous limit uses for the scene's viscous terms [m^2/s].
template <int D>
double effective_viscosity(const Simulation<D>& sim);

template <int D>
CflLimits cfl_limits(const Simulation<D>& sim);
// The same limits for given largest fluid speed and acceleration (a device run reduces them there).
template <int D>
CflLimits cfl_limits(const Simulation<D>& sim, double v_max, double a_max);

}  // namespace varsph
