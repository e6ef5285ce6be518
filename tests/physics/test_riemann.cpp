// Riemann-solver dissipation of Zhang, Hu & Adams 2017 (physics/riemann.hpp): the pair term alone, then
// a noisy periodic box (momentum to round-off, kinetic energy dissipated, thread-count independence).
#include <omp.h>

#include <random>

#include "core/errors.hpp"
#include "physics/riemann.hpp"
#include "toolbox_support.hpp"

using namespace varsph;
using namespace varsph::toolbox_test;

TEST(Riemann, DissipationActsOnApproachOnlyQuadraticWhenWeakLinearInShocks) {
  const Real rho0 = 1000, c0 = 20, eta = 3, r = Real(0.01);
  const physics::RiemannDissipation d(rho0, c0, eta);
  auto pi = [&](Real ua) { return double(d.pi(-ua * r, r * r, rho0, rho0)); };  // v_ij . x_ij = -u_a r
  EXPECT_EQ(pi(-0.5), 0.0);  // separating pair: no dissipation
  EXPECT_EQ(pi(0.0), 0.0);
  // weak compression (eta u_a / c0 < 1): beta = eta u_a / c0, Pi = rho0 c0 beta u_a / rho^2 = eta u_a^2 / rho0
  EXPECT_NEAR(pi(0.2), eta * 0.04 / rho0, 1e-12);
  EXPECT_NEAR(pi(0.4) / pi(0.2), 4.0, 1e-9);
  // strong compression (u_a >= c0 / eta): beta = 1, linear: Pi = c0 u_a / rho0
  EXPECT_NEAR(pi(10.0), c0 * 10.0 / rho0, 1e-9);
  EXPECT_NEAR(pi(20.0) / pi(10.0), 2.0, 1e-9);
}

TEST(Riemann, DensityDissipationIgnoresTheHydrostaticPressureJump) {
  // p_i - p_j = rho0 g . x_ij exactly (hydrostatic): no density change; a dynamic jump: one of its sign
  const Vec<2> g(0, Real(-9.81));
  const physics::RiemannDiffusion<2> d(1000, 20, g);
  const Vec<2> xij(Real(0.003), Real(0.004));  // x_i above x_j by 4 mm
  const Real F = Real(-1e5), V = Real(1e-4);    // F < 0: grad_i W = F x_ij points from i to j
  const Real p_j = 500, p_i = p_j + Real(1000) * g.dot(xij);
  EXPECT_NEAR(double(d.term_p(p_i, p_j, 1000, V, F, xij)), 0.0, 1e-9);
  EXPECT_LT(double(d.term_p(p_i + 100, p_j, 1000, V, F, xij)), 0.0);  // i over-pressured: its density drops
}

namespace {
json noisy_box() {
  const int n = 20;
  const double dx = 0.05, L = n * dx;
  return {{"name", "riemann_box"},
          {"setup", "paper"}, {"dimension", 2},
          {"domain", {{"min", {0.0, 0.0}}, {"max", {L, L}}, {"periodic", {true, true}}}},
          {"particles", {{"spacing", dx}}},
          {"kernel", {{"type", "wendland_c2"}, {"h_over_dx", 1.5}}},
          {"fluid", {{"rho0", 1000.0}, {"c0", 10.0}}},
          {"bodies", {{{"kind", "fluid"}, {"shape", "box"}, {"min", {0.0, 0.0}}, {"max", {L, L}}}}},
          {"physics", {{"density", "continuity"}, {"riemann", json::object()}}},
          {"integrator", {{"type", "symplectic_euler"}, {"cfl", 0.2}}},
          {"time", {{"end", 0.5}}}};
}
void randomise(Simulation<2>& sim) {
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0, 0.3);
  auto& f = sim.fields();
  for (std::size_t i = 0; i < sim.size(); ++i) f.v[i] = Vec<2>(Real(n(rng)), Real(n(rng)));
}
}  // namespace

TEST(Riemann, PeriodicBoxConservesMomentumDissipatesEnergyAndIsThreadCountIndependent) {
  std::vector<Vec<2>> x[2];
  for (int k = 0; k < 2; ++k) {
    omp_set_num_threads(k + 1);
    Simulation<2> sim(parse(noisy_box()));
    randomise(sim);
    auto momentum = [&] {
      Vec<2> p = Vec<2>::Zero();
      for (std::size_t i = 0; i < sim.size(); ++i) p += sim.fields().mass[i] * sim.fields().v[i];
      return p;
    };
    const Vec<2> p0 = momentum();
    const double ke0 = kinetic_energy(sim);
    for (int s = 0; s < 200; ++s) sim.advance();
    const double dp = double((momentum() - p0).norm()), ke = kinetic_energy(sim);
    std::printf("[%d thread(s)] |momentum change| %.2e kg m/s (initial %.3e), kinetic energy %.4f -> %.4f J\n", k + 1,
                dp, double(p0.norm()), ke0, ke);
    EXPECT_LT(dp, 1e-10 * (sim.size() * 2.5 * 0.3));  // round-off of sum m v over 400 particles
    EXPECT_LT(ke, 0.9 * ke0);                         // the random motion is dissipated
    x[k].assign(sim.size(), Vec<2>::Zero());
    for (std::size_t i = 0; i < sim.size(); ++i) x[k][std::size_t(sim.fields().id[i])] = sim.fields().x[i];
  }
  omp_set_num_threads(1);
  for (std::size_t i = 0; i < x[0].size(); ++i) ASSERT_EQ(x[0][i], x[1][i]) << "particle " << i;
}

// Why a scene with physics.riemann and integrator.type "verlet_dsph" is refused (scene/parse_scene.cpp): the
// Riemann density dissipation is a diffusion, and verlet_dsph's leapfrog density update (rho^{n+1} =
// rho^{n-1} + 2 dt drho^n) amplifies a diffusion's parasitic mode by about (1 + lambda dt) per step, too fast
// for its Euler step every 40 at this term's strength. The 2D dam break of DualSPHysics' validation at
// dx = 0.04 m, CFL 0.2, dynamic walls: verlet_dsph (the parse rule bypassed) drives the fluid pressure to
// more than 20 times rho0 g H within 40 steps (measured: 2.2 MPa at step 20 at dx = 0.02); the paper's
// kick-drift-kick Verlet stays within 3 times it (start-up included). If this ever stops failing,
// verlet_dsph has changed and the rule can go.
TEST(Riemann, VerletDsphsLeapfrogDensityUpdateAmplifiesItsDissipationSoTheCombinationIsRefused) {
  const json dam = {
      {"name", "riemann_dam"},
      {"setup", "paper"}, {"dimension", 2},
      {"domain", {{"min", {-0.2, -0.2}}, {"max", {4.2, 3.5}}}},
      {"particles", {{"spacing", 0.04}}},
      {"kernel", {{"type", "wendland_c2"}, {"h_over_dx", 1.414}}},
      {"fluid", {{"rho0", 1000.0}, {"c0", 88.4}}},
      {"gravity", {0.0, -9.81}},
      {"bodies",
       {{{"kind", "fluid"}, {"shape", "box"}, {"min", {0.0, 0.0}}, {"max", {1.0, 2.0}}, {"initial_pressure", "hydrostatic"}},
        {{"kind", "boundary"}, {"shape", "tank"}, {"min", {0.0, 0.0}}, {"max", {4.0, 3.0}}, {"layers", 3}}}},
      {"physics", {{"density", "continuity"}, {"riemann", json::object()}}},
      {"boundary", {{"model", "dynamic"}}},
      {"integrator", {{"type", "verlet"}, {"cfl", 0.2}}},
      {"time", {{"end", 1.0}}}};
  json refused = dam;
  refused["integrator"]["type"] = "verlet_dsph";
  EXPECT_THROW((void)parse(refused), InputError);

  const double rho_g_H = 1000 * 9.81 * 2.0;
  double peak[2] = {0, 0};
  omp_set_num_threads(1);
  for (int k = 0; k < 2; ++k) {
    scene::Scene sc = parse(dam);
    if (k == 1) sc.integrator = "verlet_dsph";  // the parse rule bypassed (euler_every keeps its default, 40)
    Simulation<2> sim(sc);
    for (int s = 0; s < 40; ++s) {
      sim.advance();
      for (std::size_t i = 0; i < sim.size(); ++i)
        if (sim.fields().kind[i] == 0 /* fluid */)
          peak[k] = std::max(peak[k], std::abs(double(sim.fields().p[i])) / rho_g_H);
    }
  }
  std::printf("peak |p| / (rho0 g H) over 40 steps: verlet %.2f, verlet_dsph %.2f\n", peak[0], peak[1]);
  EXPECT_LT(peak[0], 3.0);
  EXPECT_GT(peak[1], 20.0);
}
