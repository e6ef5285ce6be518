#include "integrators/rk4.hpp"

namespace varsph {

template <int D>
StepReport Rk4Integrator<D>::step(Simulation<D>& sim) {
  using namespace integrators;
  auto& f = sim.fields();
  const bool continuity = !summation_mode(sim);
  evaluate_rates(sim);  // k_1 at phi_n
  sim.set_dt(sim.choose_dt());
  const Real dt = Real(sim.dt());
  scratch_.save_base(sim);
  auto& x0 = *scratch_.x0;
  auto& v0 = *scratch_.v0;
  auto& rho0 = *scratch_.rho0;
  auto& kx = *scratch_.kx;
  auto& kv = *scratch_.kv;
  auto& krho = *scratch_.krho;
  // weights of k_s in the final sum and offsets c_{s+1} of the next stage (Chalk 2020 app. B)
  const Real weight[4] = {Real(1) / 6, Real(1) / 3, Real(1) / 3, Real(1) / 6};
  const Real next[3] = {Real(0.5), Real(0.5), Real(1)};
  for (int s = 0; s < 4; ++s) {
    if (s > 0) {
      sim.sort_and_bin();
      evaluate_rates(sim);  // k_{s+1} at phi_{s+1}
    }
    const Real w = weight[s];
    const Real c = s < 3 ? next[s] * dt : Real(0);
    const bool first = s == 0, last = s == 3;
    for_each_particle(sim.size(), [&](std::size_t i) {
      if (continuity && density_integrated(sim, i)) {
        krho[i] = (first ? Real(0) : krho[i]) + w * f.drho[i];
        f.rho[i] = last ? rho0[i] + dt * krho[i] : rho0[i] + c * f.drho[i];
      }
      if (f.kind[i] != 0) return;
      kx[i] = (first ? Vec<D>::Zero().eval() : kx[i]) + w * f.v[i];
      kv[i] = (first ? Vec<D>::Zero().eval() : kv[i]) + w * f.a[i];
      if (last) {
        f.x[i] = x0[i] + dt * kx[i];
        f.v[i] = v0[i] + dt * kv[i];
      } else {
        f.x[i] = x0[i] + c * f.v[i];  // uses the stage velocity before it is replaced
        f.v[i] = v0[i] + c * f.a[i];
      }
    });
  }
  finish_step(sim);
  return {};
}

template class Rk4Integrator<2>;
template class Rk4Integrator<3>;

}  // namespace varsph
