// The toolbox terms, each shown by its effect: laminar viscosity (Poiseuille start-up, Morris 1997),
// damping, XSPH, gravity ramp, density diffusion and the artificial stress against tensile instability.
#include <omp.h>

#include <cstring>
#include <numbers>

#include "toolbox_support.hpp"

using namespace varsph;
using namespace varsph::toolbox_test;

namespace {

// A periodic 2D box of n x n particles of spacing dx, no gravity, c0 given, rho0 = 1000.
json periodic_box(int n, double dx, double c0, double t_end) {
  const double L = n * dx;
  return {{"name", "periodic_box"},
          {"setup", "paper"}, {"dimension", 2},
          {"domain", {{"min", {0.0, 0.0}}, {"max", {L, L}}, {"periodic", {true, true}}}},
          {"particles", {{"spacing", dx}}},
          {"kernel", {{"type", "gaussian"}, {"h_over_dx", 1.2}}},
          {"fluid", {{"rho0", 1000.0}, {"c0", c0}}},
          {"bodies", {{{"kind", "fluid"}, {"shape", "box"}, {"min", {0.0, 0.0}}, {"max", {L, L}}}}},
          {"physics", {{"density", "continuity"}}},
          {"integrator", {{"type", "verlet"}, {"cfl", 0.2}}},
          {"time", {{"end", t_end}}}};
}

void add_noise(Simulation<2>& sim, double vstd, double xstd, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, 1);
  auto& f = sim.fields();
  for (std::size_t i = 0; i < sim.size(); ++i) {
    for (int a = 0; a < 2; ++a) {
      f.v[i][a] += Real(vstd * n(rng));
      f.x[i][a] += Real(xstd * n(rng));
    }
  }
}

// Poiseuille start-up series, analytic_references.md (Morris et al. 1997)
double poiseuille(double y, double t, double F, double nu, double L) {
  double u = F / (2 * nu) * y * (L - y);
  for (int n = 0; n < 20; ++n) {
    const double k = 2 * n + 1;
    u -= 4 * F * L * L / (nu * std::pow(std::numbers::pi, 3) * k * k * k) * std::sin(k * std::numbers::pi * y / L) *
         std::exp(-k * k * std::numbers::pi * std::numbers::pi * nu * t / (L * L));
  }
  return u;
}

json poiseuille_scene(const std::string& slip) {
  const double L = 1.0, dx = L / 20, Lx = 12 * dx;
  return {{"name", "poiseuille"},
          {"setup", "paper"}, {"dimension", 2},
          {"domain", {{"min", {0.0, -5 * dx}}, {"max", {Lx, L + 5 * dx}}, {"periodic", {true, false}}}},
          {"particles", {{"spacing", dx}}},
          {"kernel", {{"type", "gaussian"}, {"h_over_dx", 1.2}}},
          {"fluid", {{"rho0", 1000.0}, {"c0", 20.0}}},
          {"bodies",
           {{{"kind", "fluid"}, {"shape", "box"}, {"min", {0.0, 0.0}}, {"max", {Lx, L}}},
            {{"kind", "boundary"}, {"shape", "tank"}, {"min", {0.0, 0.0}}, {"max", {Lx, L}}, {"layers", 4},
             {"open", {true, true, false, false}}}}},
          {"physics", {{"density", "continuity"}, {"laminar_viscosity", {{"nu", 1.0}}}, {"body_force", {8.0, 0.0}}}},
          {"boundary", {{"model", "dummy_adami"}, {"slip", slip}}},
          {"integrator", {{"type", "verlet"}, {"cfl", 0.2}}},
          {"time", {{"end", 0.5}}}};
}

// mean u_x per particle row (20 rows)
std::vector<std::pair<double, double>> rows(const Simulation<2>& sim, double dx) {
  std::vector<double> su(20, 0), sy(20, 0);
  std::vector<int> c(20, 0);
  const auto& f = sim.fields();
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.kind[i] != 0) continue;
    const int b = std::clamp(int(f.x[i][1] / dx), 0, 19);
    su[b] += f.v[i][0];
    sy[b] += f.x[i][1];
    ++c[b];
  }
  std::vector<std::pair<double, double>> out;
  for (int b = 0; b < 20; ++b)
    if (c[b]) out.push_back({sy[b] / c[b], su[b] / c[b]});
  return out;
}

}  // namespace

TEST(LaminarViscosity, PoiseuilleStartUpMatchesTheSeriesSolution) {
  // L = 1 m, nu = 1 m^2/s, F = 8 m/s^2: u_max = F L^2 / (8 nu) = 1 m/s; no-slip dummy walls (Adami)
  Simulation<2> sim(parse(poiseuille_scene("no_slip")));
  const double dx = 0.05, F = 8, nu = 1, L = 1, umax = 1;
  for (double t : {0.05, 0.1, 0.2, 0.5}) {
    run_until(sim, t);
    double err = 0;
    for (auto [y, u] : rows(sim, dx)) err = std::max(err, std::abs(u - poiseuille(y, sim.time(), F, nu, L)));
    std::printf("Poiseuille t = %.3f: max |u - u_series| = %.4f m/s (%.2f %% of u_max)\n", sim.time(), err,
                100 * err / umax);
    EXPECT_LT(err, 0.03 * umax) << "t = " << t;
  }
}

TEST(LaminarViscosity, FreeSlipWallsGiveAPlugFlow) {
  // same channel, free-slip walls: no wall shear, the row next to the wall accelerates almost freely (u ~ F t)
  Simulation<2> sim(parse(poiseuille_scene("free_slip")));
  run_until(sim, 0.2);
  const auto r = rows(sim, 0.05);
  const double u_wall_row = r.front().second, u_noslip = poiseuille(r.front().first, 0.2, 8, 1, 1);
  std::printf("free-slip: u next to the wall %.3f m/s (no-slip series %.3f, free acceleration F t = %.3f)\n",
              u_wall_row, u_noslip, 8 * 0.2);
  EXPECT_GT(u_wall_row, 0.8 * 8 * 0.2);
}

TEST(LaminarViscosity, CouetteStartUpWithAMovingWallMatchesTheSeriesSolution) {
  // wall velocity is an input: the upper wall's particles carry v = (V, 0) (a prescribed tangential motion of a
  // periodic wall; they are not moved), no body force. Series of analytic_references.md, V = 1, L = 1, nu = 1.
  json j = poiseuille_scene("no_slip");
  j["physics"]["body_force"] = {0.0, 0.0};
  Simulation<2> sim(parse(j));
  auto& f = sim.fields();
  for (std::size_t i = 0; i < sim.size(); ++i)
    if (f.kind[i] == 1 && f.x[i][1] > 0.5) f.v[i] = Vec<2>(1, 0);
  sim.update_pressure();  // re-extrapolates the dummy-wall velocities with the new wall velocity
  const auto couette = [](double y, double t) {
    double u = y;
    for (int n = 1; n < 60; ++n)
      u += 2 / (n * std::numbers::pi) * (n % 2 ? -1 : 1) * std::sin(n * std::numbers::pi * y) *
           std::exp(-n * n * std::numbers::pi * std::numbers::pi * t);
    return u;
  };
  for (double t : {0.05, 0.1, 0.5}) {
    run_until(sim, t);
    double err = 0;
    for (auto [y, u] : rows(sim, 0.05)) err = std::max(err, std::abs(u - couette(y, sim.time())));
    std::printf("Couette t = %.3f: max |u - u_series| = %.4f m/s (%.2f %% of V)\n", sim.time(), err, 100 * err);
    EXPECT_LT(err, 0.03) << "t = " << t;
  }
}

TEST(Damping, KineticEnergyDecaysAsExpMinus2MuTThenStops) {
  // uniform translation of a periodic lattice: the pair forces vanish, so v ~ exp(-mu t), KE ~ exp(-2 mu t)
  json j = periodic_box(16, 0.05, 10, 1.0);
  j["physics"]["damping"] = {{"mu", 2.0}, {"until", 0.5}};
  j["bodies"][0]["velocity"] = {0.3, 0.1};
  Simulation<2> sim(parse(j));
  const double ke0 = kinetic_energy(sim);
  run_until(sim, 0.25);
  const double r0 = kinetic_energy(sim) / ke0, t0 = sim.time();
  run_until(sim, 0.75);  // damping stopped at 'until' = 0.5 (the step that starts before 0.5 still damps)
  const double r1 = kinetic_energy(sim) / ke0;
  run_until(sim, 1.0);
  const double r2 = kinetic_energy(sim) / ke0;
  std::printf("damping mu = 2/s: KE(%.3f)/KE(0) = %.4f, exp(-2 mu t) = %.4f; KE(0.75)/KE(0) = %.4f, "
              "exp(-2 mu until) = %.4f; KE(1.0)/KE(0) = %.4f\n",
              t0, r0, std::exp(-4.0 * t0), r1, std::exp(-2.0), r2);
  EXPECT_NEAR(r0, std::exp(-4.0 * t0), 0.02 * std::exp(-4.0 * t0));
  EXPECT_NEAR(r1, std::exp(-2.0), 0.02 * std::exp(-2.0));
  EXPECT_NEAR(r2, r1, 1e-3 * r1) << "damping must stop at 'until'";
}

TEST(Damping, OscillatingColumnLosesEnergyAsExpMinusMuT) {
  // a column released at rho0 without hydrostatic pressure bounces (acoustic mode, period ~ 4 H / c0 = 0.04 s);
  // for an oscillation F = -mu v removes energy as exp(-mu t): the KE averaged over [0.2, 0.3] s with mu = 5/s
  // against the same run without damping should be about exp(-mu 0.25) = 0.287 (artificial viscosity acts in both)
  double ke[2];
  for (int k = 0; k < 2; ++k) {
    json j = tank_scene(0.3, 0.2, 0.02, "dynamic");
    j["bodies"][0]["initial_pressure"] = "zero";
    if (k == 1) j["physics"]["damping"] = {{"mu", 5.0}};
    Simulation<2> sim(parse(j));
    run_until(sim, 0.2);
    double s = 0;
    int n = 0;
    while (sim.time() < 0.3) {
      sim.advance();
      s += kinetic_energy(sim);
      ++n;
    }
    ke[k] = s / n;
  }
  std::printf("oscillating column: mean KE over [0.2, 0.3] s damped / undamped = %.3f, exp(-mu 0.25) = %.3f\n",
              ke[1] / ke[0], std::exp(-1.25));
  EXPECT_NEAR(ke[1] / ke[0], std::exp(-1.25), 0.1 * std::exp(-1.25));
}

TEST(Xsph, SmoothsTheDriftVelocityOfANoisyLattice) {
  // random velocities (std 0.05 m/s) on a periodic lattice: spread of the drift velocity v + dv_xsph, and
  // the positional disorder after 0.2 s, with epsilon = 0 (off) and 0.5
  double spread[2], disorder[2];
  for (int k = 0; k < 2; ++k) {
    json j = periodic_box(20, 0.05, 10, 0.2);
    j["physics"]["artificial_viscosity"] = {{"alpha", 0.1}};
    if (k == 1) j["physics"]["xsph"] = {{"epsilon", 0.5}};
    Simulation<2> sim(parse(j));
    add_noise(sim, 0.05, 0, 7);
    auto& f = sim.fields();
    std::vector<Vec<2>> x0(sim.size());
    std::vector<std::int64_t> id0(sim.size());
    for (std::size_t i = 0; i < sim.size(); ++i) x0[f.id[i]] = f.x[i];
    const Vec<2>* dv = k == 1 ? sim.compute_xsph() : nullptr;
    double s2 = 0;
    for (std::size_t i = 0; i < sim.size(); ++i) s2 += (f.v[i] + (dv ? dv[i] : Vec<2>::Zero())).squaredNorm();
    spread[k] = std::sqrt(s2 / sim.size());
    run_until(sim, 0.2);
    // displacement spread (periodic: the displacements are small against the box)
    Vec<2> mean = Vec<2>::Zero();
    std::vector<Vec<2>> d(sim.size());
    for (std::size_t i = 0; i < sim.size(); ++i) {
      d[i] = f.x[i] - x0[f.id[i]];
      for (int a = 0; a < 2; ++a) d[i][a] -= Real(1.0) * std::round(d[i][a] / 1.0);  // box length 1 m
      mean += d[i];
    }
    mean /= Real(sim.size());
    double q = 0;
    for (auto& v : d) q += (v - mean).squaredNorm();
    disorder[k] = std::sqrt(q / sim.size());
  }
  std::printf("XSPH eps 0.5: drift-velocity spread %.4f -> %.4f m/s (x%.2f); displacement spread after 0.2 s "
              "%.5f -> %.5f m (x%.2f)\n",
              spread[0], spread[1], spread[1] / spread[0], disorder[0], disorder[1], disorder[1] / disorder[0]);
  EXPECT_LT(spread[1], 0.8 * spread[0]);
  EXPECT_LT(disorder[1], 0.8 * disorder[0]);
}

TEST(GravityRamp, ReducesTheInitialPressureOvershoot) {
  // fluid at rest at rho0 (no initial hydrostatic pressure), gravity switched on at once or ramped over 0.2 s;
  // peak of the bottom-row mean pressure / rho0 g (H - y_row) over 0.6 s
  double peak[2];
  for (int k = 0; k < 2; ++k) {
    json j = tank_scene(0.3, 0.2, 0.02, "dynamic");
    j["bodies"][0]["initial_pressure"] = "zero";
    if (k == 1) j["physics"]["gravity_ramp"] = {{"duration", 0.2}};
    Simulation<2> sim(parse(j));
    peak[k] = 0;
    while (sim.time() < 0.6) {
      sim.advance();
      const auto& f = sim.fields();
      double s = 0;
      int c = 0;
      for (std::size_t i = 0; i < sim.size(); ++i)
        if (f.kind[i] == 0 && f.x[i][1] < 0.02) { s += f.p[i]; ++c; }
      peak[k] = std::max(peak[k], s / c / (1000 * 9.81 * (0.2 - 0.01)));
    }
  }
  std::printf("gravity ramp: peak bottom pressure / hydrostatic = %.3f without ramp, %.3f with a 0.2 s ramp\n",
              peak[0], peak[1]);
  EXPECT_GT(peak[0], 1.3);
  EXPECT_LT(peak[1], 1.1);
}

TEST(TensileInstability, ArtificialStressPreventsClumpingUnderTension) {
  // periodic lattice at rho = 0.98 rho0 (p = B (0.98^7 - 1) < 0 everywhere), tiny position noise
  double dmin[2];
  for (int k = 0; k < 2; ++k) {
    json j = periodic_box(20, 0.05, 10, 1.0);
    j["physics"]["artificial_viscosity"] = {{"alpha", 0.1}};
    if (k == 1) j["physics"]["tensile_instability"] = {{"type", "artificial_stress"}};
    Simulation<2> sim(parse(j));
    add_noise(sim, 0, 0.005 * 0.05, 3);
    for (std::size_t i = 0; i < sim.size(); ++i) sim.fields().rho[i] = Real(980);
    sim.sort_and_bin();
    sim.update_pressure();
    run_until(sim, 1.0);
    const auto& f = sim.fields();
    double d2 = 1e9;
    for (std::size_t i = 0; i < sim.size(); ++i)
      for (std::size_t m = i + 1; m < sim.size(); ++m) {
        Vec<2> r = f.x[i] - f.x[m];
        for (int a = 0; a < 2; ++a) r[a] -= Real(std::round(double(r[a])));  // box 1 m
        d2 = std::min(d2, double(r.squaredNorm()));
      }
    dmin[k] = std::sqrt(d2) / 0.05;
  }
  std::printf("tension p < 0: minimum pair distance after 1 s = %.3f dx without, %.3f dx with artificial stress\n",
              dmin[0], dmin[1]);
  EXPECT_LT(dmin[0], 0.5);
  EXPECT_GT(dmin[1], 0.7);
}

TEST(Toolbox, AllTermsTogetherAreThreadCountIndependent) {
  // every optional pass at once (dummy walls + soft force, both viscosities, XSPH, damping, ramp, Fourtakas,
  // artificial stress): 1 and 2 threads give bitwise identical states (each particle writes its own slot)
  json j = tank_scene(0.3, 0.2, 0.02, "soft_repulsive");
  j["physics"]["laminar_viscosity"] = {{"nu", 1e-6}};
  j["physics"]["xsph"] = {{"epsilon", 0.5}};
  j["physics"]["damping"] = {{"mu", 1.0}, {"until", 0.01}};
  j["physics"]["gravity_ramp"] = {{"duration", 0.01}};
  j["physics"]["density_diffusion"] = {{"type", "fourtakas"}};
  j["physics"]["tensile_instability"] = {{"type", "artificial_stress"}};
  std::vector<Vec<2>> x[2];
  std::vector<Real> rho[2];
  for (int k = 0; k < 2; ++k) {
    omp_set_num_threads(k + 1);
    Simulation<2> sim(parse(j));
    for (int s = 0; s < 100; ++s) sim.advance();
    x[k] = sim.fields().x.data;
    rho[k] = sim.fields().rho.data;
  }
  omp_set_num_threads(1);
  ASSERT_EQ(x[0].size(), x[1].size());
  EXPECT_EQ(std::memcmp(x[0].data(), x[1].data(), x[0].size() * sizeof(Vec<2>)), 0);
  EXPECT_EQ(std::memcmp(rho[0].data(), rho[1].data(), rho[0].size() * sizeof(Real)), 0);
}
