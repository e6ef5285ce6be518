#include "integrators/symplectic_euler.hpp"

#include "physics/pair_loop.hpp"

namespace varsph {

template <int D>
StepReport SymplecticEulerIntegrator<D>::step(Simulation<D>& sim) {
  auto& f = sim.fields();
  // a_n at (x_n, v_n, rho_n); p_n is current (constructor, previous step or density re-initialisation)
  sim.rates().acceleration(sim.grid(), sim.current_view(), f.a.data.data());
  sim.set_dt(sim.choose_dt());
  const Real dt = Real(sim.dt());
  sim.advance_bodies(dt, 1.0);  // rigid bodies: V += dt F/M, X += dt V (the fluid's kick and drift)
  Vec<D>* x = f.x.data.data();
  Vec<D>* v = f.v.data.data();
  const Vec<D>* a = f.a.data.data();
  const std::int32_t* kind = f.kind.data.data();
  for_each_particle(sim.size(), [&](std::size_t i) {
    if (kind[i] != 0) return;
    v[i] += dt * a[i];  // v_{n+1} = v_n + dt a_n
    x[i] += dt * v[i];  // x_{n+1} = x_n + dt v_{n+1}
  });
  sim.sort_and_bin();
  sim.apply_shifting();  // physics.shifting (no-op unless named)
  sim.update_density_after_move(dt);  // rho_{n+1} from (x_{n+1}, v_{n+1}), then p_{n+1}
  return {};
}

template class SymplecticEulerIntegrator<2>;
template class SymplecticEulerIntegrator<3>;

}  // namespace varsph
