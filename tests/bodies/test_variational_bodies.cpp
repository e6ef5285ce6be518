// Rigid bodies under the paper's variational integrator (integrators/variational.cpp, eq. 63): the bodies
// take the exact reaction of (1 - alpha) a1 + alpha a2 (+ Gamma_k), so fluid and bodies exchange momentum to
// round-off; a floating box is carried; threads and a restart give the same bits.
#include <gtest/gtest.h>

#include <omp.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "bodies/rigid_bodies.hpp"
#include "integrators/variational.hpp"
#include "scene/scene.hpp"
#include "sim/diagnostics.hpp"
#include "sim/simulation.hpp"
#include "restart_support.hpp"
#include "test_support.hpp"

using namespace varsph;
using nlohmann::json;

namespace {

// A fully periodic box of water at rest with a disc and a block on a collision course (an isolated system),
// under the variational integrator with the given wall model.
json periodic_variational(const std::string& model, double alpha) {
  json j = json::parse(R"({
    "name": "periodic_bodies_variational", "setup": "paper", "dimension": 2,
    "domain": {"min": [0, 0], "max": [0.4, 0.3], "periodic": [true, true]}, "particles": {"spacing": 0.01},
    "kernel": {"type": "wendland_c2", "h_over_dx": 1.414}, "fluid": {"c0": 15},
    "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0], "max": [0.4, 0.3]},
               {"kind": "rigid", "shape": "sphere", "center": [0.13, 0.15], "radius": 0.04, "density": 3000,
                "velocity": [1.5, 0.1], "angular_velocity": [5]},
               {"kind": "rigid", "shape": "box", "min": [0.2, 0.11], "max": [0.28, 0.19], "density": 1500}],
    "physics": {"artificial_viscosity": {"alpha": 0.1}},
    "integrator": {"type": "variational", "cfl": 0.2, "fixed_point": {"on_failure": "halve_dt"}},
    "time": {"end": 1}})");
  j["boundary"] = {{"model", model}};
  j["integrator"]["alpha"] = alpha;
  return j;
}

Eigen::Vector3d fluid_momentum(const Simulation<2>& sim) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  const auto& f = sim.fields();
  for (std::size_t i = 0; i < sim.size(); ++i)
    if (f.kind[i] == 0) p += Eigen::Vector3d(double(f.mass[i] * f.v[i][0]), double(f.mass[i] * f.v[i][1]), 0);
  return p;
}

}  // namespace

// v_{k+1/2} of the fluid and V_{k+1/2} of the bodies change by equal and opposite impulses: the total stays
// at its initial value to round-off, for the dynamic walls (the reaction of a1 and a2) and the repulsive walls
// (the reaction of Gamma_k at q_k), at alpha 0.5 and 0.
TEST(VariationalBodies, FluidAndBodiesKeepTheirTotalMomentumToRoundOff) {
  for (const auto& [model, alpha] : std::vector<std::pair<std::string, double>>{{"dynamic", 0.5}, {"repulsive", 0.5},
                                                                                  {"dynamic", 0.0}}) {
    Simulation<2> sim(scene::parse_scene_json(periodic_variational(model, alpha), "periodic.json"));
    auto* rb = sim.rigid_bodies();
    const Eigen::Vector3d P0 = fluid_momentum(sim) + rb->momentum();
    const double scale = rb->bodies()[0].mp.mass * 1.5;
    const double v0 = rb->bodies()[0].v.x(), x1 = rb->bodies()[1].x.x();
    double worst = 0;
    while (sim.time() < 0.025) {
      sim.advance();
      worst = std::max(worst, (fluid_momentum(sim) + rb->momentum() - P0).norm());
    }
    std::printf("%s, alpha %.1f: |P - P0| <= %.3g of %.3g kg m/s over %ld steps; disc vx %.4f -> %.4f, block moved %.3g m\n",
                model.c_str(), alpha, worst, scale, sim.step(), v0, rb->bodies()[0].v.x(), rb->bodies()[1].x.x() - x1);
    EXPECT_LT(worst, 1e-11 * scale) << model << " alpha " << alpha;
    EXPECT_LT(rb->bodies()[0].v.x(), 0.995 * v0) << model;  // the fluid slowed the disc: the exchange was real
  }
}

TEST(VariationalBodies, TwoThreadsGiveTheBitsOfOne) {
  auto run = [](int threads) {
    omp_set_num_threads(threads);
    Simulation<2> sim(scene::parse_scene_json(periodic_variational("dynamic", 0.5), "periodic.json"));
    for (int n = 0; n < 30; ++n) sim.advance();
    omp_set_num_threads(1);
    std::map<std::int64_t, std::array<double, 4>> by_id;
    const auto& f = sim.fields();
    for (std::size_t i = 0; i < sim.size(); ++i)
      by_id[f.id[i]] = {double(f.x[i][0]), double(f.x[i][1]), double(f.v[i][0]), double(f.v[i][1])};
    return std::make_pair(sim.rigid_bodies()->save_state().dump(), by_id);
  };
  const auto one = run(1), two = run(2);
  EXPECT_EQ(one.first, two.first);
  EXPECT_TRUE(one.second == two.second);
}

TEST(VariationalBodies, ARestartContinuesBitwise) {
  namespace fs = std::filesystem;
  const fs::path dir = test::scratch_dir("variational_rigid_restart");
  json j = periodic_variational("dynamic", 0.5);
  j["time"]["end"] = 0.01;
  j["output"] = {{"every", 0.005}, {"probes_every", 0.001}};
  j["checkpoint"] = {{"every", 0.005}};
  std::ofstream(dir / "scene.json") << j.dump(1);
  const auto t = test::run_full_and_restarted(dir / "scene.json", dir, "0.005", "bodies.csv");
  ASSERT_TRUE(t.error.empty()) << t.error;
  const std::string& full = t.full;
  EXPECT_EQ(full, t.continued);
  EXPECT_GT(std::count(full.begin(), full.end(), '\n'), 8);
}

// The box of pipelines/bodies/floating_box_2d.json at its Archimedes draft with the paper's set-up (repulsive
// walls, eq. 58), alpha = 0.5: the fluid carries its weight (mean vertical fluid force
// over 0.25-0.5 s within 5 % of M g; measured 1.1 % repulsive, as `verlet` gives 0.3 % on the same window. Over
// 0.1-0.25 s, while the box still settles, the variational run reads 19 % low and `verlet` 7.6 %).
TEST(VariationalBodies, TheFluidCarriesAFloatingBox) {
  for (const std::string model : {"repulsive"}) {  // dynamic walls: the momentum test above
    const std::vector<std::string> o = {"particles.spacing=0.02", "time.end=0.5", "bodies.2.min=[0.5, 0.35]",
                                        "bodies.2.max=[0.7, 0.45]", "boundary.model=\"" + model + "\"",
                                        "physics.riemann=null", "physics.artificial_viscosity={\"alpha\": 0.1}",
                                        "integrator={\"type\": \"variational\", \"alpha\": 0.5, \"cfl\": 0.2}"};
    Simulation<2> sim(scene::parse_scene(test::source_dir() / "pipelines" / "bodies" / "floating_box_2d.json", o));
    const auto& b = sim.rigid_bodies()->bodies().at(0);
    double sum = 0, w = 0;
    while (sim.time() < 0.5) {
      sim.advance();
      if (sim.time() > 0.25) {
        sum += b.loads.fluid_force.y() * sim.dt();
        w += sim.dt();
      }
    }
    const double weight = b.mp.mass * 9.81;
    std::printf("variational, %s: mean fluid force %.2f N/m, weight %.2f N/m, centre %.4f m, %ld steps\n",
                model.c_str(), sum / w, weight, b.x.y(), sim.step());
    EXPECT_NEAR(sum / w / weight, 1.0, 0.05) << model;
  }
}

// Issue 30 point 5, energy beside momentum: the ledger diagnostics.csv writes (fluid kinetic + Tait internal
// energy + the bodies' kinetic energy; no gravity here) in the isolated periodic box, while the disc gives
// more than half its energy to the water. Symplectic Euler without any dissipation term keeps it within a few
// per cent (the dynamic walls' own compression energy is not in the ledger); with artificial viscosity it
// falls. The variational integrator keeps the momentum to round-off (above) but loses more energy (measured
// and printed; docs/bodies.md "Energy") - it must at least never create any.
TEST(VariationalBodies, TheCoupledEnergyLedgerNeverGrowsAndItsLossIsBounded) {
  // measured on 2026-11-27 (lowest / highest ledger against E0):
  //   symplectic Euler, continuity density: -6.95 % / +0.12 %
  //   variational, continuity density: -12.1 % / 0 (-11.4 % / +8e-8 % with the bodies frozen at q_k through the
  //     fixed point, before they joined it)
  //   variational, summation density (the discrete Lagrangian's own density, eq. 19-20): -7.0 % / +8e-6 %
  // The coupling is not where the variational run loses its extra 5 points: the continuity density (eq. 67,
  // not derived from the Lagrangian) is; with summation it loses what symplectic Euler does.
  struct Case { const char* integrator; const char* density; double floor; };
  for (const Case c : {Case{"symplectic_euler", "continuity", 0.9}, Case{"variational", "continuity", 0.85},
                       Case{"variational", "summation", 0.9}}) {
    json j = periodic_variational("dynamic", 0.5);
    j["physics"] = {{"density", c.density}};  // no dissipation term
    if (std::string(c.integrator) == "symplectic_euler") j["integrator"] = {{"type", "symplectic_euler"}, {"cfl", 0.2}};
    Simulation<2> sim(scene::parse_scene_json(j, "periodic.json"));
    const auto ledger = [&] {
      const Diagnostics d = compute_diagnostics(sim);
      return d.kinetic_energy + d.internal_energy + d.bodies_kinetic_energy;
    };
    const double E0 = ledger(), Eb0 = compute_diagnostics(sim).bodies_kinetic_energy;
    double lo = E0, hi = E0;
    while (sim.time() < 0.025) {
      sim.advance();
      const double E = ledger();
      lo = std::min(lo, E);
      hi = std::max(hi, E);
    }
    const double Eb = compute_diagnostics(sim).bodies_kinetic_energy;
    std::printf("%s, %s density, no dissipation term: E0 %.6g J/m, over %ld steps E in [%+.3g %%, %+.3g %%] of E0; "
                "bodies' kinetic %.4g -> %.4g\n",
                c.integrator, c.density, E0, sim.step(), 100 * (lo / E0 - 1), 100 * (hi / E0 - 1), Eb0, Eb);
    EXPECT_LT(Eb, 0.6 * Eb0) << c.integrator;  // the exchange was real: the disc gave most of its energy away
    EXPECT_GT(lo, E0 * c.floor) << c.integrator << ' ' << c.density;
    EXPECT_LT(hi, E0 * (std::string(c.integrator) == "variational" ? 1 + 1e-6 : 1.01)) << c.integrator;
  }
}

// Issue 30 point 2: the bodies are unknowns of the variational integrator's fixed point, not boundary
// particles frozen at q_k. At the last evaluation of every converged step the fixed point evaluated a1 with
// the body's particles at the generalised midpoint (1 - alpha) x_k + alpha x_{k+1} of the step it accepted
// (to the iteration's tolerance), and the residual it converged on covers them. With the bodies frozen at q_k
// (the coupling before 2026-11-27) they sat a whole alpha dt |V| (3.4e-4 m here) away from that point.
TEST(VariationalBodies, TheFixedPointSolvesForTheBodiesMidpoint) {
  Simulation<2> sim(scene::parse_scene_json(periodic_variational("dynamic", 0.5), "periodic.json"));
  auto& integ = dynamic_cast<VariationalIntegrator<2>&>(sim.integrator());
  const auto& f = sim.fields();
  const auto body_positions = [&](std::span<const Vec<2>> x) {
    std::map<std::int64_t, Vec<2>> m;
    for (std::size_t i = 0; i < sim.size(); ++i)
      if (f.kind[i] != 0 && sim.rigid_bodies()->is_rigid(f.body[i])) m[f.id[i]] = x[i];
    return m;
  };
  std::map<std::int64_t, Vec<2>> last_eval;
  integ.on_evaluation = [&](const NeighborGrid<2>&, std::span<const Vec<2>> x) { last_eval = body_positions(x); };
  const double tol = 1e-6 * 0.01;  // the fixed point's default tolerance, 1e-6 of the spacing (docs/scene.md)
  double worst = 0, shift = 0;
  for (int n = 0; n < 20; ++n) {
    const auto xk = body_positions(f.x.data);
    sim.advance();
    const auto xk1 = body_positions(f.x.data);
    ASSERT_EQ(last_eval.size(), xk.size());
    for (const auto& [id, x0] : xk) {
      const Vec<2> expected = Real(0.5) * (x0 + xk1.at(id));
      worst = std::max(worst, double((last_eval.at(id) - expected).norm()));
      shift = std::max(shift, double((last_eval.at(id) - x0).norm()));
    }
  }
  std::printf("body particles at the last evaluation: <= %.3g m from (x_k + x_{k+1}) / 2, up to %.3g m from x_k\n",
              worst, shift);
  EXPECT_LT(worst, tol);
  EXPECT_GT(shift, 100 * tol);  // not trivially x_k: the body moved
}

// The contraction watch and the dt bound (eq. 52-54) see the bodies: a very light body answers the fluid's
// forces fast, so the coupled fixed point contracts more slowly than with a heavy one, and the bound falls.
TEST(VariationalBodies, ALightBodyTightensTheFixedPointsContraction) {
  const auto run = [](double density) {
    json j = periodic_variational("dynamic", 0.5);
    j["bodies"][1]["density"] = density;
    Simulation<2> sim(scene::parse_scene_json(j, "periodic.json"));
    int iterations = 0;
    double contraction = 0;
    for (int n = 0; n < 30; ++n) {
      const StepReport r = sim.advance();
      iterations += r.iterations;
      contraction = std::max(contraction, r.contraction);
    }
    std::printf("disc of %g kg/m^3: %d iterations in 30 steps, largest contraction %.3g, dt bound %.3g s (dt %.3g s)\n",
                density, iterations, contraction, sim.integrator().dt_bound(), sim.dt());
    return std::make_pair(iterations, contraction);
  };
  const auto heavy = run(3000), light = run(30);
  EXPECT_GT(light.second, 2 * heavy.second);  // measured 2026-11-27: 0.188 against 0.030
}
