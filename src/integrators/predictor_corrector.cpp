#include "integrators/predictor_corrector.hpp"

namespace varsph {

template <int D>
StepReport PredictorCorrectorIntegrator<D>::step(Simulation<D>& sim) {
  using namespace integrators;
  auto& f = sim.fields();
  evaluate_rates(sim);  // F_n
  sim.set_dt(sim.choose_dt());
  const Real dt = Real(sim.dt()), half = Real(0.5) * dt;
  const bool continuity = !summation_mode(sim);
  scratch_.save_base(sim);
  // predictor (Monaghan 1989): half step with the rates at n
  for_each_particle(sim.size(), [&](std::size_t i) {
    if (continuity && density_integrated(sim, i)) f.rho[i] += half * f.drho[i];
    if (f.kind[i] != 0) return;
    f.x[i] += half * f.v[i];
    f.v[i] += half * f.a[i];
  });
  sim.sort_and_bin();
  evaluate_rates(sim);  // F_{n+1/2}
  auto& x0 = *scratch_.x0;
  auto& v0 = *scratch_.v0;
  auto& rho0 = *scratch_.rho0;
  // corrector and f_{n+1} = 2 f_c - f_n
  for_each_particle(sim.size(), [&](std::size_t i) {
    if (continuity && density_integrated(sim, i)) f.rho[i] = rho0[i] + dt * f.drho[i];
    if (f.kind[i] != 0) return;
    const Vec<D> vc = v0[i] + half * f.a[i];
    f.v[i] = v0[i] + dt * f.a[i];
    f.x[i] = x0[i] + dt * vc;
  });
  finish_step(sim);
  return {};
}

template class PredictorCorrectorIntegrator<2>;
template class PredictorCorrectorIntegrator<3>;

}  // namespace varsph
