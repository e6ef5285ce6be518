#pragma once
// Variational (generalized-midpoint) time integrator of the seed paper, eq. (63)-(65), Algorithm 1.
//
// Kept in velocity form: with v_{k-1/2} = (q_k - q_{k-1}) / dt (eq. 57/60) the step
//   q_{k+1} = 2 q_k - q_{k-1} + dt^2 [(1-alpha) a1 + alpha a2]                          (eq. 63)
// is v_{k+1/2} = v_{k-1/2} + dt [(1-alpha) a1 + alpha a2],  q_{k+1} = q_k + dt v_{k+1/2}, so q_{k-1} is
// never stored (periodic wraps cannot separate it from q_k) and midpoints are
//   (1-alpha) q_{k-1} + alpha q_k = q_k - (1-alpha) dt v_{k-1/2}   (a2, eq. 30-31)
//   (1-alpha) q_k + alpha q_{k+1} = q_k + alpha dt v_{k+1/2}       (a1, eq. 20-21).
// a1 and a2 carry pressure (eq. 64-65), Monaghan viscosity from the midpoint velocities (eq. 55-57,
// PAPER-NOTES.md) and gravity, evaluated at their midpoint configuration with the midpoint densities
// (continuity, eq. 67-68 with the standard sign, or summation, eq. 20/30); the wall force Gamma_k
// (eq. 58) is evaluated at q_k once per step and added to both (eq. 64-65).
// State between steps: x = q_k, v = v_{k-1/2}, rho = rho_{k-1,k} (density of the a2 midpoint), and the
// registered field "variational_a2" = a2 without Gamma (the a1 of the previous step, reused).
// alpha = 1 is the Verlet scheme (eq. 60-62) and runs through verlet_step(), the same code as `verlet`.
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "integrators/verlet.hpp"
#include "physics/repulsive_wall.hpp"
#include "physics/simd/sweep_args.hpp"
#include "sim/simulation.hpp"

namespace varsph {

template <int D>
class VariationalIntegrator final : public Integrator<D> {
 public:
  explicit VariationalIntegrator(const scene::Scene& s);
  const char* name() const override { return "variational"; }
  bool implicit() const override { return true; }
  double dt_bound() const override { return last_bound_; }
  void initialize(Simulation<D>& sim) override;
  StepReport step(Simulation<D>& sim) override;
  bool one_region_step() const override { return true; }  // core/team.hpp's rules hold in step()
  nlohmann::json save_state() const override;
  void restore_state(const nlohmann::json& j) override;

  double alpha() const { return alpha_; }
  // True when a1 does not depend on q_{k+1}: alpha = 1, or alpha = 0 without viscosity and with
  // summation density. Otherwise each step is a fixed-point iteration.
  bool explicit_scheme() const { return explicit_; }
  // Observed contraction of the fixed-point map on the current state (power iteration on
  // F(q + d) - F(q), no state changed) and the eq. (54) bound dt / sqrt(c); 0 when explicit.
  double estimate_contraction(Simulation<D>& sim);
  double estimate_dt_bound(Simulation<D>& sim);

  // --- for tests and benchmarks ---------------------------------------------------------------------
  // Called with the grid and every configuration a pass is evaluated at (midpoints, q_k).
  std::function<void(const NeighborGrid<D>&, std::span<const Vec<D>>)> on_evaluation;
  // Runs exactly n iterations per step and accepts the result (0: normal convergence control).
  void set_fixed_iterations(int n) { fixed_iterations_ = n; }
  // Initial guess of the iteration: true (default) extrapolates a1 linearly from the last two steps' a2
  // when they had the same dt; false takes a1 = a2 (the guess before issue 19). Either converges to the
  // same fixed point (the map F is the same); only the number of iterations changes.
  void set_extrapolated_predictor(bool on) { extrapolate_ = on; }
  // a2 of the next step (fluid part, without Gamma), and a fresh evaluation of it on the current state.
  std::span<const Vec<D>> cached_a2() const { return a2_->data; }
  void fresh_a2(Simulation<D>& sim, std::vector<Vec<D>>& out);
  int halvings() const { return halvings_; }

 private:
  struct EvalResult {
    Real max_shift;  // largest fluid displacement of the evaluated configuration from x
  };
  void register_fields(Simulation<D>& sim);
  // Widens the skin (and re-bins) when needed; false when the grid cannot cover the displacement.
  bool ensure_skin(Simulation<D>& sim, Real displacement);
  // Midpoint configuration x + s v (fluid only) into mid_; returns the largest shift, < 0 if uncoverable.
  Real make_midpoint(Simulation<D>& sim, std::span<const Vec<D>> v, Real s);
  // Densities, pressures and fluid accelerations (no Gamma) at mid_ with velocities v; density from
  // rho_base + dt_rho * drho (continuity) or by summation.
  void eval_midpoint(Simulation<D>& sim, std::span<const Vec<D>> v, Real dt_rho, Vec<D>* a_out);
  void compute_gamma(Simulation<D>& sim);
  // Gamma_k and the rigid bodies' loads at q_k (contact, moorings, the reaction of Gamma_k): once per step
  void loads_at_qk(Simulation<D>& sim);
  // Rebuilds rho_{k-1,k} and a2 so they belong to the previous interval seen with step dt_new
  // (q_{k-1} = q_k - dt_new v_{k-1/2}); rho moves by (1-alpha)(dt_old - dt_new) drho.
  void rebuild_previous(Simulation<D>& sim, double dt_old, double dt_new);
  // One fixed-point solve for the step dt; true when converged (or explicit / fixed count).
  bool solve(Simulation<D>& sim, Real dt, StepReport& rep, std::string& history);
  // Open boundaries: the buffer particles' entries of a velocity iterate set to their prescribed chord.
  void hold_buffers(Simulation<D>& sim, Vec<D>* v_out);
  // F applied to the velocity iterate v_in -> v_out (one evaluation of a1).
  bool apply_F(Simulation<D>& sim, Real dt, std::span<const Vec<D>> v_in, Vec<D>* v_out);

  double alpha_;
  double tol_;  // [m]
  int max_it_;
  bool halve_on_failure_;
  physics::simd::Isa isa_;  // the vectorised sweep for the wall-force pass (physics/simd/)
  bool explicit_ = false;
  bool has_wall_ = false;
  std::span<const Vec<D>> eval_v_;  // the velocities of the last midpoint evaluation (rigid bodies' loads)
  // Rigid bodies: the reaction of the last midpoint evaluation on them (bodies/rigid_bodies.hpp)
  void body_midpoint_loads(Simulation<D>& sim, bool replace);
  bool summation_ = false;
  int fixed_iterations_ = 0;
  static constexpr int kDivergenceWindow = 3;  // c_j >= 1 this many times in a row: diverging
  static constexpr int kMaxHalvings = 12;
  static constexpr int kRegrowAfter = 100;  // accepted steps at reduced dt before trying to double it

  // scalar state (checkpointed through save_state)
  double dt_prev_ = 0;      // dt of the interval [t_{k-1}, t_k] that rho_{k-1,k} and a2 belong to
  int halvings_ = 0;        // current dt = scene dt / 2^halvings
  long steps_since_change_ = 0;
  double last_bound_ = 0;
  bool skin_ok_ = true;           // ensure_skin's answer, shared by a step region's threads
  bool predictor_ready_ = false;  // a2_prev_ and a2_ belong to two consecutive intervals of the same dt
  bool extrapolate_ = true;

  std::unique_ptr<physics::Rates<D>> fluid_rates_;  // the scene's rates without the wall force
  std::unique_ptr<physics::RepulsiveWall> wall_;
  // registered fields
  Field<Vec<D>>* a2_ = nullptr;       // state (checkpointed)
  Field<Vec<D>>* a2_prev_ = nullptr;  // a2 of the previous step, for the predictor (checkpointed)
  Field<Vec<D>>* mid_ = nullptr;
  Field<Vec<D>>* vit_ = nullptr;
  Field<Vec<D>>* vnew_ = nullptr;
  Field<Vec<D>>* a1_ = nullptr;
  Field<Vec<D>>* gamma_ = nullptr;
  Field<Real>* rho1_ = nullptr;
  Field<Real>* p1_ = nullptr;
  Field<Real>* drho1_ = nullptr;
  std::vector<double> residuals_;  // reserved once (no allocation in the iteration)
};

}  // namespace varsph
