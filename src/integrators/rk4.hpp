#pragma once
// Classical fourth-order Runge-Kutta (Chalk 2020 appendix B; foundation notes "RK4") on the whole
// state phi = (x, v, rho) of the fluid: k_s = (v_s, a_s, drho_s) at phi_s,
//   phi_2 = phi_n + dt/2 k_1, phi_3 = phi_n + dt/2 k_2, phi_4 = phi_n + dt k_3,
//   phi_{n+1} = phi_n + dt/6 (k_1 + 2 k_2 + 2 k_3 + k_4).
// Four rate evaluations per step; particles are re-binned (sort_and_bin) before each stage, and the
// base state and the accumulated increments are registered fields, so they follow the permutation.
#include "integrators/explicit_stages.hpp"

namespace varsph {

template <int D>
class Rk4Integrator final : public Integrator<D> {
 public:
  const char* name() const override { return "rk4"; }
  void initialize(Simulation<D>& sim) override { scratch_.register_in(sim, "rk4", true); }
  StepReport step(Simulation<D>& sim) override;

 private:
  integrators::StageScratch<D> scratch_;
};

}  // namespace varsph
