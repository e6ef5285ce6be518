#pragma once
// Symplectic Euler (semi-implicit Euler, Euler-Cromer; foundation notes "Symp Euler", taichiCourse01-10):
// all rates at the state n (x_n, v_n, rho_n): v_{n+1} = v_n + dt a_n, x_{n+1} = x_n + dt v_{n+1},
// rho_{n+1} = rho_n + dt drho_n (continuity; summation recomputes rho at x_{n+1}). First order.
// v is the velocity at integer times t_n, started from v(0) without a shift. This is the foundation's
// `verlet` update loop read with integer-time velocities: the notes' "Leap-Frog" (half-step update from
// the previous rate, then positions from the end-of-step velocity) is also of this first-order kind.
#include "sim/simulation.hpp"

namespace varsph {

template <int D>
class SymplecticEulerIntegrator final : public Integrator<D> {
 public:
  const char* name() const override { return "symplectic_euler"; }
  void initialize(Simulation<D>&) override {}
  StepReport step(Simulation<D>& sim) override;
};

}  // namespace varsph
