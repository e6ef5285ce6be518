#pragma once
// Symplectic Euler (semi-implicit Euler, Euler-Cromer; foundation notes "Symp Euler", taichiCourse01-10),
// first order. v is the velocity at integer times t_n, started from v(0) unshifted:
//   a_n = a(x_n, v_n, rho_n);  v_{n+1} = v_n + dt a_n;  x_{n+1} = x_n + dt v_{n+1};
//   rho_{n+1} = rho_n + dt drho(x_{n+1}, v_{n+1})   (continuity; summation: rho(x_{n+1})).
// The density is advanced like a position, with the new velocity: (x, rho) are the "coordinates" and v
// the "momentum" of the symplectic pair. Advancing rho with drho(x_n, v_n) instead would make the
// acoustic subsystem (rho, v) a forward Euler step, which grows without bound (it blew up the dam break).
// This is the same update loop as the foundation's `verlet`; that scheme differs only in reading v as the
// half-step velocity v_{n-1/2} with a shifted start, which makes its positions second order.
#include "sim/simulation.hpp"

namespace varsph {

template <int D>
class SymplecticEulerIntegrator final : public Integrator<D> {
 public:
  const char* name() const override { return "symplectic_euler"; }
  void initialize(Simulation<D>&) override {}
  StepReport step(Simulation<D>& sim) override;
  bool one_region_step() const override { return true; }  // core/team.hpp's rules hold in step()
};

}  // namespace varsph
