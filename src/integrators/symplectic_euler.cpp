#include "integrators/symplectic_euler.hpp"

#include "integrators/explicit_stages.hpp"

namespace varsph {

template <int D>
StepReport SymplecticEulerIntegrator<D>::step(Simulation<D>& sim) {
  integrators::evaluate_rates(sim);  // a_n, drho_n at (x_n, v_n, rho_n)
  sim.set_dt(sim.choose_dt());
  const Real dt = Real(sim.dt());
  auto& f = sim.fields();
  const bool continuity = !integrators::summation_mode(sim);
  for_each_particle(sim.size(), [&](std::size_t i) {
    if (continuity && integrators::density_integrated(sim, i)) f.rho[i] += dt * f.drho[i];
    if (f.kind[i] != 0) return;
    f.v[i] += dt * f.a[i];  // v_{n+1} = v_n + dt a_n
    f.x[i] += dt * f.v[i];  // x_{n+1} = x_n + dt v_{n+1}
  });
  integrators::finish_step(sim);
  return {};
}

template class SymplecticEulerIntegrator<2>;
template class SymplecticEulerIntegrator<3>;

}  // namespace varsph
