#include "integrators/variational.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "bodies/rigid_bodies.hpp"
#include "core/errors.hpp"
#include "core/team.hpp"
#include "physics/pair_loop.hpp"
#include "physics/passes.hpp"
#include "parallel/communicator.hpp"
#include "physics/repulsive_wall.hpp"
#include "integrators/variational_passes.hpp"
#include "physics/simd/isa.hpp"
#include "physics/simd/vector_sweep.hpp"

namespace varsph {
namespace {

}  // namespace
}  // namespace varsph

// The vectorised sweep runs WallOnlyPass (integrators/variational_passes.hpp) as a walls-only pass: the
// candidate test in packs, the wall pairs through the pass's own pair() (physics/simd/vector_sweep.hpp).
namespace varsph::physics::simd {
template <int D>
struct FluidTerms<::varsph::WallOnlyPass<D>> {
  static constexpr bool covered = true;
  static const ParticleView<D>& view(const ::varsph::WallOnlyPass<D>& p) { return p.s; }
  static void fill(SweepArgs& A, const ::varsph::WallOnlyPass<D>& p) {
    A.rc2 = double(p.support) * double(p.support);
    A.walls_only = true;
  }
  static void add(Vec<D>&, const double*) {}
};
}  // namespace varsph::physics::simd

namespace varsph {
namespace {

template <int D>
physics::PhysicsParams<D> without_wall(physics::PhysicsParams<D> p) {
  p.wall_D = 0;  // the wall force is evaluated separately at q_k (Gamma_k of eq. 64-65)
  return p;
}

}  // namespace

template <int D>
VariationalIntegrator<D>::VariationalIntegrator(const scene::Scene& s)
    : alpha_(s.alpha),
      tol_(s.fp_absolute_tolerance ? *s.fp_absolute_tolerance : s.fp_tolerance * s.spacing),
      max_it_(s.fp_max_iterations),
      halve_on_failure_(s.fp_on_failure == "halve_dt"), isa_(physics::simd::choose_isa()) {
  summation_ = s.density == "summation";
  // alpha = 0: a1 sits at q_k; it still depends on q_{k+1} through the viscosity (midpoint velocity
  // (q_{k+1} - q_k)/dt) and the continuity density (eq. 67), so only this case is explicit.
  const bool viscous = s.riemann || (s.artificial_viscosity && (s.av_alpha > 0 || s.av_beta > 0));
  explicit_ = alpha_ == 1.0 || (alpha_ == 0.0 && summation_ && !viscous);
}

template <int D>
void VariationalIntegrator<D>::register_fields(Simulation<D>& sim) {
  auto& st = sim.store();
  const FieldFlags scratch{.exported = false, .checkpointed = false};
  a2_ = &st.template add<Vec<D>>("variational_a2", {.exported = false, .checkpointed = true});
  a2_prev_ = &st.template add<Vec<D>>("variational_a2_prev", {.exported = false, .checkpointed = true});
  mid_ = &st.template add<Vec<D>>("variational_midpoint", scratch);
  vit_ = &st.template add<Vec<D>>("variational_v_iterate", scratch);
  vnew_ = &st.template add<Vec<D>>("variational_v_next", scratch);
  a1_ = &st.template add<Vec<D>>("variational_a1", scratch);
  gamma_ = &st.template add<Vec<D>>("variational_wall_force", scratch);
  rho1_ = &st.template add<Real>("variational_rho_iterate", scratch);
  p1_ = &st.template add<Real>("variational_p_iterate", scratch);
  drho1_ = &st.template add<Real>("variational_drho", scratch);
  std::fill(gamma_->data.begin(), gamma_->data.end(), Vec<D>::Zero());
  std::fill(a2_->data.begin(), a2_->data.end(), Vec<D>::Zero());
  std::fill(a2_prev_->data.begin(), a2_prev_->data.end(), Vec<D>::Zero());
  // benchmark switch for the initial guess (docs/performance.md): extrapolated (default) or constant
  if (const char* e = std::getenv("VARSPH_VARIATIONAL_PREDICTOR")) {
    const std::string want = e;
    if (want != "extrapolated" && want != "constant")
      throw InputError("VARSPH_VARIATIONAL_PREDICTOR=" + want + ": expected extrapolated or constant");
    extrapolate_ = want == "extrapolated";
  }
  residuals_.reserve(std::size_t(max_it_) + 2);
}

template <int D>
void VariationalIntegrator<D>::initialize(Simulation<D>& sim) {
  verlet_initialize(sim);  // v(-1/2) = v(0) - dt g / 2 (section 5.3): q_{-1} = q_0 - dt v(-1/2)
  if (alpha_ == 1.0) return;
  register_fields(sim);
  const auto& p = sim.params();
  has_wall_ = p.boundary == physics::BoundaryModel::Repulsive && p.wall_D > 0;
  if (explicit_) {
    // alpha = 0 explicit: a1 sits at q_k like Gamma_k, so the wall force stays in the same pass; the
    // step is then the Verlet step with summation density, bit for bit.
    has_wall_ = false;
    fluid_rates_ = sim.make_rates(p);  // (with the halo exchange of a distributed run)
  } else {
    fluid_rates_ = sim.make_rates(without_wall(p));
  }
  if (has_wall_) wall_ = std::make_unique<physics::RepulsiveWall>(p.wall_D, p.wall_r0, p.wall_n1, p.wall_n2);
  // Skin: 5 % of the support radius to start; ensure_skin() widens it whenever a configuration to be
  // evaluated would move a particle by more than skin/2 from the binned q_k.
  dt_prev_ = sim.dt();
  if (explicit_) return;  // a2 has weight 0 and every pass sits at q_k: no skin needed
  sim.set_skin(Real(0.05) * sim.rates().support());
  sim.sort_and_bin();
  rebuild_previous(sim, 0.0, sim.dt());  // rho_{-1,0} and a2 at (1-alpha) q_{-1} + alpha q_0
  last_bound_ = estimate_dt_bound(sim);
}

template <int D>
bool VariationalIntegrator<D>::ensure_skin(Simulation<D>& sim, Real displacement) {
  // A pair closer than the support in a configuration whose particles moved <= d from the binned one
  // was closer than support + 2 d when binned: cells of support + skin cover it if d <= skin / 2.
  if (Real(2) * displacement <= sim.skin()) return true;
  const Real old = sim.skin();
  for (const Real skin : {std::max(Real(2) * old, Real(4) * displacement), Real(2.0001) * displacement}) {
    try {
      sim.set_skin(skin);
      // the same configuration q_k re-binned (every registered field, scratch included, follows the
      // permutation); not sort_and_bin(), which would move walls and open-boundary buffers to t_{k+1}
      sim.rebin();
      return true;
    } catch (const InputError&) {  // cells too large for a (periodic) domain: the step moves too far
    }
  }
  sim.set_skin(old);
  sim.rebin();
  return false;
}

template <int D>
Real VariationalIntegrator<D>::make_midpoint(Simulation<D>& sim, std::span<const Vec<D>> v, Real s) {
  auto& f = sim.fields();
  const std::size_t n = sim.size();
  // fluid particles, and the particles of rigid bodies (unknowns of the fixed point like the fluid: their
  // entry of v is their chord velocity); every other boundary particle stays at q_k
  const auto* bodies = sim.rigid_bodies();
  const std::int32_t* kind = f.kind.data.data();
  const std::int32_t* body = f.body.data.data();
  const auto moves = [&](std::size_t i) { return kind[i] == 0 || (bodies && bodies->is_rigid(body[i])); };
  Real vmax = 0;  // a max: the same for any thread count
  {
    const Vec<D>* vv = v.data();
    vmax = Real(team_max2(long(n), [&](long i, double& m, double&) {
                  if (moves(std::size_t(i))) m = std::max(m, double(vv[i].squaredNorm()));
                }).first);
  }
  vmax = Real(sim.global_max(double(vmax)));  // every rank widens the skin together
  const Real shift = std::abs(s) * std::sqrt(vmax);
  if (!std::isfinite(shift)) return -1;
  if (Real(2) * shift > sim.skin()) {  // the grid must widen: re-sorts (once per team, core/team.hpp)
    team_single([&] { skin_ok_ = ensure_skin(sim, shift); });
    if (!skin_ok_) return -1;
    kind = f.kind.data.data();  // the sort permuted every field in place
    body = f.body.data.data();
  }
  Vec<D>* m = mid_->data.data();
  const Vec<D>* x = f.x.data.data();
  const Vec<D>* vv = v.data();
  for_each_particle(n, [&](std::size_t i) { m[i] = moves(i) ? Vec<D>(x[i] + s * vv[i]) : x[i]; });
  return shift;
}

template <int D>
void VariationalIntegrator<D>::eval_midpoint(Simulation<D>& sim, std::span<const Vec<D>> v, Real dt_rho,
                                             Vec<D>* a_out) {
  auto& f = sim.fields();
  const std::size_t n = sim.size();
  const auto& grid = sim.grid();
  if (on_evaluation) team_single([&] { on_evaluation(grid, mid_->data); });
  Real* rho1 = rho1_->data.data();
  Real* p1 = p1_->data.data();
  const Real* rho = f.rho.data.data();
  // extrapolated walls (dummy / mDBC): their state of q_k (loads_at_qk), with the velocities the viscosity sees
  const auto with_walls = [&](physics::ParticleView<D> view) {
    const auto cur = sim.current_view();
    view.wall_v = cur.wall_v;
    view.normal = cur.normal;
    return view;
  };
  const physics::ParticleView<D> base =
      with_walls({mid_->data, v, f.rho.data, f.p.data, f.mass.data, f.kind.data});
  // open-boundary buffer particles keep their imposed density (held like walls; null without open boundaries)
  const std::int32_t* held = sim.open_zones();
  if (summation_) {
    for_each_particle(n, [&](std::size_t i) { rho1[i] = rho[i]; });  // the slots the pass leaves alone
    fluid_rates_->summation_density(grid, base, rho1);  // seed eq. (20)/(30) at the midpoint
    if (held)
      for_each_particle(n, [&](std::size_t i) {
        if (held[i] >= 0) rho1[i] = rho[i];
      });
  } else {
    Real* drho = drho1_->data.data();
    fluid_rates_->density_rate(grid, base, drho);  // eq. (67)-(68), standard sign
    const std::int32_t* kind = f.kind.data.data();
    const bool walls = sim.params().boundary == physics::BoundaryModel::Dynamic;
    if (held)
      for_each_particle(n, [&](std::size_t i) {
        rho1[i] = ((kind[i] == 0 && held[i] < 0) || (kind[i] != 0 && walls)) ? rho[i] + dt_rho * drho[i] : rho[i];
      });
    else
      for_each_particle(n, [&](std::size_t i) { rho1[i] = (kind[i] == 0 || walls) ? rho[i] + dt_rho * drho[i] : rho[i]; });
  }
  const auto eos = sim.eos();
  for_each_particle(n, [&](std::size_t i) { p1[i] = eos.pressure(rho1[i]); });  // eq. (26)-(27), (35)-(36)
  const physics::ParticleView<D> s = with_walls({mid_->data, v, rho1_->data, p1_->data, f.mass.data, f.kind.data});
  fluid_rates_->acceleration(grid, s, a_out);  // eq. (64)/(65) without Gamma
  team_single([&] { eval_v_ = v; });
}

template <int D>
void VariationalIntegrator<D>::body_midpoint_loads(Simulation<D>& sim, bool replace) {
  auto* bodies = sim.rigid_bodies();
  if (!bodies) return;
  auto& f = sim.fields();
  // the view of the last eval_midpoint: its positions, velocities, densities and pressures
  const physics::ParticleView<D> s{mid_->data, eval_v_, rho1_->data, p1_->data, f.mass.data, f.kind.data};
  bodies->midpoint_loads(sim, *fluid_rates_, s, replace);
}

template <int D>
void VariationalIntegrator<D>::loads_at_qk(Simulation<D>& sim) {
  // dummy / mDBC walls: pressure, density and no-slip velocity extrapolated from the fluid at q_k, where eq.
  // (64)-(65) evaluate the boundary (Gamma_k); held through the step's midpoints like the walls' positions
  if (sim.walls_extrapolated()) sim.update_pressure();
  compute_gamma(sim);
  if (auto* bodies = sim.rigid_bodies()) bodies->variational_begin(sim, has_wall_);
}

template <int D>
void VariationalIntegrator<D>::compute_gamma(Simulation<D>& sim) {
  if (!has_wall_) return;
  const auto view = sim.current_view();
  sim.refresh_halo(view);  // distributed runs: ghosts at q_k
  if (on_evaluation) team_single([&] { on_evaluation(sim.grid(), sim.fields().x.data); });
  WallOnlyPass<D> pass{*wall_, view, gamma_->data.data(), sim.rates().support()};
  if (!physics::simd::vector_sweep<D>(isa_, sim.grid(), pass))
    for_each_particle_pairs<D>(sim.grid(), view.x, sim.rates().support(), pass);  // Gamma_k, eq. (58)
}

template <int D>
void VariationalIntegrator<D>::rebuild_previous(Simulation<D>& sim, double dt_old, double dt_new) {
  auto& f = sim.fields();
  if (make_midpoint(sim, f.v.data, Real(-(1 - alpha_) * dt_new)) < 0)  // (1-alpha) q_{k-1} + alpha q_k
    team_single([&] {
      throw NumericalError("variational: at t = " + std::to_string(sim.time()) +
                           " s the previous interval's midpoint moves particles farther than the neighbour grid "
                           "can cover (dt " + std::to_string(dt_new) + " s too large)");
    });
  eval_midpoint(sim, f.v.data, Real((1 - alpha_) * (dt_old - dt_new)), a2_->data.data());
  body_midpoint_loads(sim, true);  // the bodies' share of a2
  const Real* rho1 = rho1_->data.data();
  const Real* p1 = p1_->data.data();
  Real* rho = f.rho.data.data();
  Real* p = f.p.data.data();
  for_each_particle(rho1_->data.size(), [&](std::size_t i) {  // ghost slots included
    rho[i] = rho1[i];
    p[i] = p1[i];
  });
  team_single([&] { predictor_ready_ = false; });  // a2 now belongs to an interval of length dt_new; a2_prev does not
}

template <int D>
void VariationalIntegrator<D>::hold_buffers(Simulation<D>& sim, Vec<D>* v_out) {
  // open-boundary buffer particles: prescribed kinematics (Tafuni 2018 sec. 3.1: x_{k+1} = x_k + dt v0, v0 the
  // velocity imposed after the last step), so their chord v_{k+1/2} is v0 = the stored v, held through the
  // iteration like a boundary particle's; they still move to every midpoint with it (make_midpoint)
  const std::int32_t* held = sim.open_zones();
  if (!held) return;  // no open boundaries: nothing to hold
  const Vec<D>* v = sim.fields().v.data.data();
  for_each_particle(sim.size(), [&](std::size_t i) {
    if (held[i] >= 0) v_out[i] = v[i];
  });
}

template <int D>
bool VariationalIntegrator<D>::apply_F(Simulation<D>& sim, Real dt, std::span<const Vec<D>> v_in, Vec<D>* v_out) {
  auto& f = sim.fields();
  if (make_midpoint(sim, v_in, Real(alpha_) * dt) < 0) return false;  // (1-alpha) q_k + alpha q_{k+1}, eq. (20)-(21)
  eval_midpoint(sim, v_in, dt, a1_->data.data());
  const Real w1 = Real(1 - alpha_), w2 = Real(alpha_);
  const Vec<D>* v = f.v.data.data();
  const Vec<D>* a1 = a1_->data.data();
  const Vec<D>* a2 = a2_->data.data();
  const Vec<D>* g = gamma_->data.data();
  const std::int32_t* kind = f.kind.data.data();
  for_each_particle(sim.size(), [&](std::size_t i) {
    // eq. (63) in velocity form: v_{k+1/2} = v_{k-1/2} + dt [(1-alpha) a1 + alpha a2 + Gamma_k]
    v_out[i] = kind[i] == 0 ? Vec<D>(v[i] + dt * (w1 * a1[i] + w2 * a2[i] + g[i])) : v[i];
  });
  hold_buffers(sim, v_out);
  if (auto* bodies = sim.rigid_bodies()) {  // the bodies' trial step from the reaction of this a1
    body_midpoint_loads(sim, false);
    bodies->variational_trial(sim, dt, alpha_, false, v_out);
  }
  return true;
}

template <int D>
bool VariationalIntegrator<D>::solve(Simulation<D>& sim, Real dt, StepReport& rep, std::string& history) {
  auto& f = sim.fields();
  const std::size_t n = sim.size();
  rep = {};
  team_single([&] { residuals_.clear(); });
  if (explicit_) {  // alpha = 0, summation, no viscosity: a1 at q_k does not depend on q_{k+1}
    rep.iterations = 1;
    if (apply_F(sim, dt, f.v.data, vnew_->data.data())) return true;
    history = "a1 at q_k could not be evaluated";
    return false;
  }
  {  // explicit predictor q_{k+1;0} = 2 q_k - q_{k-1} + dt^2 [(1-alpha) a1~ + alpha a2 + Gamma_k], with a1~
     // extrapolated linearly from the a1 of the last two steps (a2 and a2_prev: the a1 midpoints are dt
     // apart when dt did not change), else a1~ = a2. The map F and its fixed point are the same either way.
    Vec<D>* vi = vit_->data.data();
    const Vec<D>* v = f.v.data.data();
    const Vec<D>* a2 = a2_->data.data();
    const Vec<D>* a2p = a2_prev_->data.data();
    const Vec<D>* g = gamma_->data.data();
    const std::int32_t* kind = f.kind.data.data();
    if (extrapolate_ && predictor_ready_) {
      const Real w1 = Real(1 - alpha_);
      for_each_particle(n, [&](std::size_t i) {
        vi[i] = kind[i] == 0 ? Vec<D>(v[i] + dt * (a2[i] + g[i] + w1 * (a2[i] - a2p[i]))) : v[i];
      });
    } else {
      for_each_particle(n, [&](std::size_t i) { vi[i] = kind[i] == 0 ? Vec<D>(v[i] + dt * (a2[i] + g[i])) : v[i]; });
    }
    hold_buffers(sim, vi);
    if (auto* bodies = sim.rigid_bodies()) bodies->variational_trial(sim, dt, alpha_, true, vi);  // R1 ~ R2
  }
  int diverging = 0;
  double prev = 0;
  bool too_far = false;
  for (int j = 1; j <= max_it_; ++j) {
    // q_{k+1;j} = F(q_{k+1;j-1}, q_k, q_{k-1}), eq. (40)
    if (!apply_F(sim, dt, vit_->data, vnew_->data.data())) {
      too_far = true;
      break;
    }
    double r2 = 0;  // a max over the fluid and the bodies' particles: the same for any thread count
    {
      const std::int32_t* kind = f.kind.data.data();
      const std::int32_t* body = f.body.data.data();
      const auto* bodies = sim.rigid_bodies();
      const Vec<D>* vn = vnew_->data.data();
      const Vec<D>* vo = vit_->data.data();
      r2 = team_max2(long(n), [&](long i, double& m, double&) {
             if (kind[i] == 0 || (bodies && bodies->is_rigid(body[i])))
               m = std::max(m, double((vn[i] - vo[i]).squaredNorm()));
           }).first;
    }
    r2 = sim.global_max(r2);  // the convergence test over every rank's particles
    const double r = double(dt) * std::sqrt(r2);  // max_i |q_{k+1;j} - q_{k+1;j-1}|
    team_single([&] { residuals_.push_back(r); });  // every thread has the same r
    const double c = (j > 1 && prev > 0) ? r / prev : 0.0;
    rep.iterations = j;
    rep.residual = r;
    rep.contraction = std::max(rep.contraction, c);
    if (fixed_iterations_ > 0) {
      if (j >= fixed_iterations_) return true;
    } else {
      if (r <= tol_) return true;
      diverging = (j > 1 && c >= 1.0) ? diverging + 1 : 0;
      if (diverging >= kDivergenceWindow) break;
    }
    prev = r;
    team_single([&] { vit_->data.swap(vnew_->data); });  // no copy, no allocation
  }
  std::ostringstream o;
  o.precision(3);
  o << (too_far ? std::string("fixed-point iterate moves particles farther than the neighbour grid can cover")
      : diverging >= kDivergenceWindow ? "fixed point diverging (contraction >= 1 for " +
                                             std::to_string(kDivergenceWindow) + " iterations)"
                                       : "fixed point not converged in " + std::to_string(max_it_) + " iterations")
    << " (alpha " << alpha_ << ", dt " << dt << " s, tolerance " << tol_ << " m); residuals [m]:";
  for (double r : residuals_) o << ' ' << r;
  history = o.str();
  return false;
}

template <int D>
StepReport VariationalIntegrator<D>::step(Simulation<D>& sim) {
  if (alpha_ == 1.0) {  // the explicit Verlet scheme, eq. (60)-(62): one code path with `verlet`
    verlet_step(sim);
    return {};
  }
  auto& f = sim.fields();
  const std::size_t n = sim.size();
  double dt = sim.choose_dt() / double(1L << halvings_);
  if (dt != dt_prev_ && !explicit_) rebuild_previous(sim, dt_prev_, dt);  // regrowth, CFL change, restart
  sim.set_dt(dt);
  loads_at_qk(sim);
  StepReport rep;
  std::string history;
  while (!solve(sim, Real(dt), rep, history)) {
    const std::string where = "step " + std::to_string(sim.step() + 1) + " (t = " + std::to_string(sim.time()) +
                              " s -> " + std::to_string(sim.time() + dt) + " s): ";
    const double dt_new = dt / 2;
    team_single([&] {  // inside a step's parallel region: once (core/team.hpp)
      if (!halve_on_failure_ || halvings_ >= kMaxHalvings)
        throw NumericalError(where + history +
                             (halve_on_failure_ ? "; dt already halved " + std::to_string(kMaxHalvings) + " times"
                                                : std::string("")) +
                             ". The state is left at the last accepted step (t = " + std::to_string(sim.time()) +
                             " s); integrator.fixed_point.on_failure = \"halve_dt\" retries with smaller steps");
      // redo the step with dt / 2: rho_{k-1,k} and a2 rebuilt for q_{k-1} = q_k - (dt/2) v_{k-1/2}
      ++halvings_;
      steps_since_change_ = 0;
      if (sim.comm().root())  // every rank takes the same decision: one message
        std::fprintf(stderr, "varsph: variational: %s%s; halving dt to %.4g s\n", where.c_str(), history.c_str(),
                     dt_new);
    });
    rebuild_previous(sim, dt, dt_new);
    dt = dt_new;
    team_single([&] { dt_prev_ = dt; });
    sim.set_dt(dt);
  }
  team_single([&] {
    if (rep.contraction > 0) last_bound_ = dt / std::sqrt(rep.contraction);  // eq. (54) with M1 ~ c
  });
  rep.dt_bound = last_bound_;
  // rigid bodies: the trial of the accepted iterate is their step (eq. 63 for them)
  if (auto* bodies = sim.rigid_bodies()) bodies->variational_accept(sim, dt);
  // accept: v_{k+1/2}, q_{k+1}; a1 (at the accepted iterate) becomes the next step's a2
  {
    const Real w1 = Real(1 - alpha_), w2 = Real(alpha_), h = Real(dt);
    Vec<D>* x = f.x.data.data();
    Vec<D>* v = f.v.data.data();
    Vec<D>* a = f.a.data.data();
    Vec<D>* a1 = a1_->data.data();
    Vec<D>* a2 = a2_->data.data();
    Vec<D>* a2p = a2_prev_->data.data();
    const Vec<D>* vn = vnew_->data.data();
    const Vec<D>* g = gamma_->data.data();
    Real* rho = f.rho.data.data();
    Real* p = f.p.data.data();
    const Real* rho1 = rho1_->data.data();
    const Real* p1 = p1_->data.data();
    const std::int32_t* kind = f.kind.data.data();
    for_each_particle(n, [&](std::size_t i) {
      rho[i] = rho1[i];  // rho_{k,k+1}: the a2 density of the next step
      p[i] = p1[i];
      if (kind[i] != 0) return;
      a[i] = w1 * a1[i] + w2 * a2[i] + g[i];
      a2p[i] = a2[i];
      a2[i] = a1[i];
      v[i] = vn[i];
      x[i] += h * v[i];  // q_{k+1} = q_k + dt v_{k+1/2}
    });
  }
  team_single([&] {
    dt_prev_ = dt;
    predictor_ready_ = true;  // a2_prev and a2: consecutive intervals of length dt
  });
  sim.sort_and_bin();
  team_single([&] {  // once (core/team.hpp); choose_dt runs serially here
    if (halvings_ > 0 && ++steps_since_change_ >= kRegrowAfter) {
      --halvings_;  // the next step sees dt != dt_prev_ and rebuilds the previous interval
      steps_since_change_ = 0;
      const double next_dt = sim.choose_dt() / double(1L << halvings_);  // collective (CFL maxima)
      if (sim.comm().root())
        std::fprintf(stderr, "varsph: variational: growing dt back to %.4g s at t = %g s\n", next_dt, sim.time() + dt);
    }
  });
  return rep;
}

template <int D>
double VariationalIntegrator<D>::estimate_contraction(Simulation<D>& sim) {
  if (explicit_ || alpha_ == 1.0) return 0;
  auto& f = sim.fields();
  const std::size_t n = sim.size();
  const Real dt = Real(sim.dt());
  loads_at_qk(sim);
  {  // widen the skin first so that no re-sort happens while local copies are held below
    Real vmax = 0;
    const auto* bodies = sim.rigid_bodies();
    for (std::size_t i = 0; i < n; ++i) {
      if (f.kind[i] == 0) vmax = std::max(vmax, (f.v[i] + dt * (a2_->data[i] + gamma_->data[i])).norm());
      else if (bodies && bodies->is_rigid(f.body[i])) vmax = std::max(vmax, Real(2) * f.v[i].norm());  // a trial's chord
    }
    vmax = Real(sim.global_max(double(vmax)));
    if (!ensure_skin(sim, Real(1.1) * Real(alpha_) * dt * vmax + Real(1e-9) * Real(sim.scene().spacing))) return 0;
  }
  std::vector<Vec<D>> v0(n), base(n), dir(n);  // setup-time only
  const std::int32_t* held = sim.open_zones();  // buffer particles: their prescribed chord, never perturbed
  for (std::size_t i = 0; i < n; ++i)
    v0[i] = f.kind[i] == 0 && !(held && held[i] >= 0) ? Vec<D>(f.v[i] + dt * (a2_->data[i] + gamma_->data[i])) : f.v[i];
  std::copy(v0.begin(), v0.end(), vit_->data.begin());  // keeps the field's ghost slots
  if (!apply_F(sim, dt, vit_->data, vnew_->data.data())) return 0;
  std::copy(vnew_->data.begin(), vnew_->data.begin() + std::ptrdiff_t(n), base.begin());
  // power iteration on d -> F(q + d) - F(q) in the max norm; deterministic start
  const Real eps = Real(1e-6) * Real(sim.scene().spacing) / dt;  // velocity perturbation (dt eps = 1e-6 dx)
  for (std::size_t i = 0; i < n; ++i) {
    Vec<D> d;
    for (int a = 0; a < D; ++a) d[a] = Real(std::sin(double(f.id[i]) * 12.9898 + a * 78.233));
    dir[i] = f.kind[i] == 0 && !(held && held[i] >= 0) ? Vec<D>(eps * d.normalized()) : Vec<D>::Zero();
  }
  double c = 0;
  for (int it = 0; it < 8; ++it) {
    double dmax = 0, omax = 0;
    for (std::size_t i = 0; i < n; ++i) {
      vit_->data[i] = v0[i] + dir[i];
      dmax = std::max(dmax, double(dir[i].norm()));
    }
    if (!apply_F(sim, dt, vit_->data, vnew_->data.data())) return 0;
    for (std::size_t i = 0; i < n; ++i) {
      dir[i] = vnew_->data[i] - base[i];
      omax = std::max(omax, double(dir[i].norm()));
    }
    dmax = sim.global_max(dmax);
    omax = sim.global_max(omax);
    c = dmax > 0 ? omax / dmax : 0;
    if (omax <= 0) break;
    for (auto& d : dir) d *= Real(double(eps) / omax);
  }
  return c;
}

template <int D>
double VariationalIntegrator<D>::estimate_dt_bound(Simulation<D>& sim) {
  const double c = estimate_contraction(sim);
  return c > 0 ? sim.dt() / std::sqrt(c) : 0.0;  // eq. (52)-(54): M1 = c, dt < 1/sqrt((1-alpha) M2)
}

template <int D>
void VariationalIntegrator<D>::fresh_a2(Simulation<D>& sim, std::vector<Vec<D>>& out) {
  // a1 of the previous step evaluated afresh at the accepted q_k, v_{k-1/2}: the previous interval's
  // midpoint q_k - (1-alpha) dt v_{k-1/2}, continuity base rho_{k-2,k-1} is not kept, so the density
  // comes from the stored rho_{k-1,k} (summation scenes recompute it).
  auto& f = sim.fields();
  out.resize(sim.store().size());  // passes may write ghost slots of the output
  if (make_midpoint(sim, f.v.data, Real(-(1 - alpha_) * dt_prev_)) < 0) throw NumericalError("fresh_a2: skin");
  eval_midpoint(sim, f.v.data, Real(0), out.data());
}

template <int D>
nlohmann::json VariationalIntegrator<D>::save_state() const {
  return {{"dt_prev", dt_prev_},
          {"halvings", halvings_},
          {"steps_since_change", steps_since_change_},
          {"dt_bound", last_bound_},
          {"predictor_ready", predictor_ready_}};
}

template <int D>
void VariationalIntegrator<D>::restore_state(const nlohmann::json& j) {
  if (j.contains("dt_prev")) dt_prev_ = j.at("dt_prev").get<double>();
  if (j.contains("halvings")) halvings_ = j.at("halvings").get<int>();
  if (j.contains("steps_since_change")) steps_since_change_ = j.at("steps_since_change").get<long>();
  if (j.contains("dt_bound")) last_bound_ = j.at("dt_bound").get<double>();
  predictor_ready_ = j.value("predictor_ready", false);
}

template class VariationalIntegrator<2>;
template class VariationalIntegrator<3>;

}  // namespace varsph
