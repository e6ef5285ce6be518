#include "integrators/verlet.hpp"

#include "physics/pair_loop.hpp"

namespace varsph {

template <int D>
void verlet_initialize(Simulation<D>& sim) {
  auto& f = sim.fields();
  const Vec<D> half_dt_g = Real(0.5 * sim.dt()) * sim.rates().body_acceleration();  // g(0): ramp, body force
  for (std::size_t i = 0; i < sim.size(); ++i)
    if (f.kind[i] == 0) f.v[i] -= half_dt_g;  // v(-1/2) = v(0) - dt g / 2
}

template <int D>
void verlet_step(Simulation<D>& sim) {
  auto& f = sim.fields();
  sim.rates().acceleration(sim.grid(), sim.current_view(), f.a.data.data());  // eq. (59)
  sim.set_dt(sim.choose_dt());
  const Real dt = Real(sim.dt());
  sim.advance_bodies(dt, 1.0);  // rigid bodies: eq. (61)-(62) for their centre and rotation
  Vec<D>* x = f.x.data.data();
  Vec<D>* v = f.v.data.data();
  const Vec<D>* a = f.a.data.data();
  const std::int32_t* kind = f.kind.data.data();
  if (!sim.xsph_enabled()) {
    for_each_particle(sim.size(), [&](std::size_t i) {
      if (kind[i] != 0) return;
      v[i] += dt * a[i];  // eq. (61)
      x[i] += dt * v[i];  // eq. (62)
    });
  } else {
    for_each_particle(sim.size(), [&](std::size_t i) {
      if (kind[i] == 0) v[i] += dt * a[i];  // eq. (61)
    });
    const Vec<D>* dv = sim.compute_xsph();  // XSPH (Monaghan 1989) from v_{k+1/2} at q_k
    for_each_particle(sim.size(), [&](std::size_t i) {
      if (kind[i] == 0) x[i] += dt * (v[i] + dv[i]);  // eq. (62) with the XSPH velocity
    });
  }
  sim.sort_and_bin();
  sim.apply_shifting();  // physics.shifting (no-op unless named)
  sim.update_density_after_move(dt);
}

template <int D>
void VerletIntegrator<D>::initialize(Simulation<D>& sim) {
  verlet_initialize(sim);
}

template <int D>
StepReport VerletIntegrator<D>::step(Simulation<D>& sim) {
  verlet_step(sim);
  return {};
}

template void verlet_initialize<2>(Simulation<2>&);
template void verlet_initialize<3>(Simulation<3>&);
template void verlet_step<2>(Simulation<2>&);
template void verlet_step<3>(Simulation<3>&);
template class VerletIntegrator<2>;
template class VerletIntegrator<3>;

}  // namespace varsph
