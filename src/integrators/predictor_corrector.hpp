#pragma once
// Monaghan's predictor-corrector (Monaghan 1989, J. Comput. Phys. 82; Monaghan 1994), second order,
// integrating (x, v, rho) together:
//   predictor  f_{n+1/2} = f_n + dt/2 F_n                       for f = v, rho, x (F = a, drho, v)
//   corrector  v_c = v_n + dt/2 a_{n+1/2},  rho_c = rho_n + dt/2 drho_{n+1/2},  x_c = x_n + dt/2 v_c
//   final      f_{n+1} = 2 f_c - f_n
// Two rate evaluations per step; the grid is rebuilt (sort_and_bin) at the half state.
#include "integrators/explicit_stages.hpp"

namespace varsph {

template <int D>
class PredictorCorrectorIntegrator final : public Integrator<D> {
 public:
  const char* name() const override { return "predictor_corrector"; }
  void initialize(Simulation<D>& sim) override { scratch_.register_in(sim, "pc", false); }
  StepReport step(Simulation<D>& sim) override;

 private:
  integrators::StageScratch<D> scratch_;
};

}  // namespace varsph
