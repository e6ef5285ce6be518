#pragma once
// Shared pieces of the explicit multi-stage schemes (symplectic Euler, predictor-corrector, RK4):
// the right-hand side of the fluid ODE d(x, v, rho)/dt = (v, a, drho) evaluated at the state held in
// the store's position/velocity/density arrays, and the scratch fields a scheme registers once.
#include <string>

#include "physics/pair_loop.hpp"
#include "sim/simulation.hpp"

namespace varsph::integrators {

// True where the density is a state variable integrated by continuity (fluid particles, and the
// boundary particles of the dynamic wall model, as Simulation::update_density_after_move does).
template <int D>
bool density_integrated(const Simulation<D>& sim, std::size_t i) {
  return sim.fields().kind[i] == 0 || sim.params().boundary == physics::BoundaryModel::Dynamic;
}

template <int D>
bool summation_mode(const Simulation<D>& sim) {
  return sim.params().density == physics::DensityMode::Summation;
}

// Rates at the state in (x, v, rho); the grid must be valid for x (call sort_and_bin first).
// Summation: rho = sum_j m_j W_ij (seed eq. 8) is recomputed from x and is not a state variable.
// Continuity: drho/dt = sum_j m_j v_ij . grad_i W_ij (Monaghan 1992) into fields().drho.
// Then p = EOS(rho) and a (seed eq. 59) into fields().a; continuity and forces in one sweep where fused.
template <int D>
void evaluate_rates(Simulation<D>& sim) {
  auto& f = sim.fields();
  if (summation_mode(sim)) sim.rates().summation_density(sim.grid(), sim.current_view(), f.rho.data.data());
  sim.update_pressure();
  if (summation_mode(sim)) sim.rates().acceleration(sim.grid(), sim.current_view(), f.a.data.data());
  else sim.rates().density_rate_and_acceleration(sim.grid(), sim.current_view(), f.drho.data.data(), f.a.data.data());
}

// Scratch registered in the particle store (so sort_and_bin permutes it with everything else);
// allocated once in initialize(), never in the step loop. Not checkpointed: it only lives within a step.
template <int D>
struct StageScratch {
  Field<Vec<D>>* x0 = nullptr;  // positions at the start of the step (position-like: wrapped with x)
  Field<Vec<D>>* v0 = nullptr;  // velocities at the start of the step
  Field<Real>* rho0 = nullptr;  // densities at the start of the step
  Field<Vec<D>>* kx = nullptr;  // weighted sums of the stage rates (RK4) / corrected half velocity
  Field<Vec<D>>* kv = nullptr;
  Field<Real>* krho = nullptr;

  void register_in(Simulation<D>& sim, const std::string& prefix, bool accumulators) {
    const FieldFlags scratch{.exported = false, .checkpointed = false};
    auto& s = sim.store();
    x0 = &s.template add<Vec<D>>(prefix + "_x0", scratch);
    v0 = &s.template add<Vec<D>>(prefix + "_v0", scratch);
    rho0 = &s.template add<Real>(prefix + "_rho0", scratch);
    sim.register_position_like(x0);
    if (accumulators) {
      kx = &s.template add<Vec<D>>(prefix + "_kx", scratch);
      kv = &s.template add<Vec<D>>(prefix + "_kv", scratch);
      krho = &s.template add<Real>(prefix + "_krho", scratch);
    }
  }

  // Copies the current state into (x0, v0, rho0).
  void save_base(Simulation<D>& sim) {
    auto& f = sim.fields();
    for_each_particle(sim.size(), [&](std::size_t i) {
      (*x0)[i] = f.x[i];
      (*v0)[i] = f.v[i];
      (*rho0)[i] = f.rho[i];
    });
  }
};

// Ends a step: the grid for the new positions; summation densities; pressures.
template <int D>
void finish_step(Simulation<D>& sim) {
  sim.sort_and_bin();
  sim.apply_shifting();  // physics.shifting (no-op unless named)
  auto& f = sim.fields();
  if (summation_mode(sim)) sim.rates().summation_density(sim.grid(), sim.current_view(), f.rho.data.data());
  sim.update_pressure();
}

}  // namespace varsph::integrators
