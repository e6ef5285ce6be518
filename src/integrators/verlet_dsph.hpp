#pragma once
// The two-level Verlet scheme of DualSPHysics (Gomez-Gesteira et al. 2012, Comput. Geosci. 48; Dominguez
// et al. 2022, Comp. Part. Mech. 9, eq. 26-27), with velocities and densities at integer times:
//   (a_n, drho_n) = rates(x_n, v_n, rho_n)            one fused neighbour sweep (continuity + forces)
//   x_{n+1}   = x_n + dt v_n + dt^2/2 a_n
//   v_{n+1}   = v_{n-1} + 2 dt a_n,  rho_{n+1} = rho_{n-1} + 2 dt drho_n
// and every `integrator.euler_every` steps (default 40) the Euler step v_{n+1} = v_n + dt a_n,
// rho_{n+1} = rho_n + dt drho_n that keeps the even and odd sequences from decoupling. The first step is
// an Euler step. Density by continuity only (the point of the scheme is the single sweep per step).
// Dynamic (DBC) walls integrate their density the same way. v_{n-1}, rho_{n-1} are registered fields
// (checkpointed), the step counter is integrator state: restarts are bitwise.
#include "sim/simulation.hpp"

namespace varsph {

template <int D>
class VerletDsphIntegrator final : public Integrator<D> {
 public:
  explicit VerletDsphIntegrator(int euler_every) : euler_every_(euler_every) {}
  const char* name() const override { return "verlet_dsph"; }
  void initialize(Simulation<D>& sim) override;
  StepReport step(Simulation<D>& sim) override;
  bool one_region_step() const override { return true; }  // core/team.hpp's rules hold in step()
  nlohmann::json save_state() const override { return {{"steps_since_euler", steps_since_euler_}}; }
  void restore_state(const nlohmann::json& j) override {
    if (j.contains("steps_since_euler")) steps_since_euler_ = j.at("steps_since_euler").get<long>();
  }

 private:
  int euler_every_;
  long steps_since_euler_ = -1;  // -1: the next step is the first (Euler)
  bool euler_now_ = true;        // this step's choice (set once per step, read by every thread)
  Field<Vec<D>>* v_prev_ = nullptr;
  Field<Real>* rho_prev_ = nullptr;
};

}  // namespace varsph
