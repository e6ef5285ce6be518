#include "integrators/verlet_dsph.hpp"

#include "integrators/explicit_stages.hpp"
#include "physics/pair_loop.hpp"

namespace varsph {

template <int D>
void VerletDsphIntegrator<D>::initialize(Simulation<D>& sim) {
  auto& st = sim.store();
  v_prev_ = &st.template add<Vec<D>>("verlet_dsph_v_prev", {.exported = false, .checkpointed = true});
  rho_prev_ = &st.template add<Real>("verlet_dsph_rho_prev", {.exported = false, .checkpointed = true});
  auto& f = sim.fields();
  for (std::size_t i = 0; i < sim.size(); ++i) {
    (*v_prev_)[i] = f.v[i];
    (*rho_prev_)[i] = f.rho[i];
  }
}

template <int D>
StepReport VerletDsphIntegrator<D>::step(Simulation<D>& sim) {
  auto& f = sim.fields();
  sim.rates().density_rate_and_acceleration(sim.grid(), sim.current_view(), f.drho.data.data(), f.a.data.data());
  sim.set_dt(sim.choose_dt());
  const Real dt = Real(sim.dt());
  team_single([&] {  // once per step, also inside a step's parallel region (core/team.hpp)
    euler_now_ = steps_since_euler_ < 0 || steps_since_euler_ + 1 >= euler_every_;
    steps_since_euler_ = euler_now_ ? 0 : steps_since_euler_ + 1;
  });
  const bool euler = euler_now_;
  // rigid bodies: V += dt A, X += dt V + dt^2/2 A (the Taylor drift the fluid uses below)
  sim.advance_bodies(dt, 0.5);
  Vec<D>* x = f.x.data.data();
  Vec<D>* v = f.v.data.data();
  Real* rho = f.rho.data.data();
  const Vec<D>* a = f.a.data.data();
  const Real* drho = f.drho.data.data();
  Vec<D>* vm1 = v_prev_->data.data();
  Real* rhom1 = rho_prev_->data.data();
  const std::int32_t* kind = f.kind.data.data();
  const bool walls_integrate = sim.params().boundary == physics::BoundaryModel::Dynamic;
  const Real half_dt2 = Real(0.5) * dt * dt;
  const Real step2 = euler ? dt : Real(2) * dt;  // Euler: from level n; Verlet: from level n-1
  const Vec<D>* dv = sim.xsph_enabled() ? sim.compute_xsph() : nullptr;  // XSPH (Monaghan 1989) at level n
  for_each_particle(sim.size(), [&](std::size_t i) {
    if (kind[i] == 0) {
      const Vec<D> vn = v[i];
      const Vec<D> vbase = euler ? vn : vm1[i];
      x[i] += dt * (dv ? Vec<D>(vn + dv[i]) : vn) + half_dt2 * a[i];  // x_{n+1} = x_n + dt v_n + dt^2/2 a_n
      v[i] = vbase + step2 * a[i];        // v_{n+1} = v_{n-1} + 2 dt a_n  (Euler: v_n + dt a_n)
      vm1[i] = vn;
    } else if (!walls_integrate) {
      return;
    }
    const Real rn = rho[i];
    rho[i] = (euler ? rn : rhom1[i]) + step2 * drho[i];  // rho_{n+1} = rho_{n-1} + 2 dt drho_n
    rhom1[i] = rn;
  });
  sim.sort_and_bin();
  sim.apply_shifting();  // physics.shifting (no-op unless named)
  sim.update_pressure();
  return {};
}

template class VerletDsphIntegrator<2>;
template class VerletDsphIntegrator<3>;

}  // namespace varsph
