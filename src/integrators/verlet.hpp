#pragma once
// Verlet / leap-frog of the seed paper, eq. (60)-(62), which is the variational scheme (63) at
// alpha = 1: a^i (eq. 59) at q_k with densities rho(q_k), viscosity from v_{k-1/2} = (q_k - q_{k-1})/dt
// (eq. 57); then v_{k+1/2} = v_{k-1/2} + dt a (61), q_{k+1} = q_k + dt v_{k+1/2} (62); the continuity
// density of the new configuration uses v_{k+1/2} at q_{k+1} (eq. 68 at alpha = 1, standard sign).
// Start: v(-1/2) = v(0) - dt g / 2 (section 5.3).
#include "sim/simulation.hpp"

namespace varsph {

template <int D>
class VerletIntegrator final : public Integrator<D> {
 public:
  const char* name() const override { return "verlet"; }
  void initialize(Simulation<D>& sim) override;
  StepReport step(Simulation<D>& sim) override;
  bool one_region_step() const override { return true; }  // core/team.hpp's rules hold in step()
};

// The one explicit alpha = 1 code path, shared by `verlet` and `variational` with alpha = 1.
template <int D>
void verlet_initialize(Simulation<D>& sim);
template <int D>
void verlet_step(Simulation<D>& sim);

}  // namespace varsph
