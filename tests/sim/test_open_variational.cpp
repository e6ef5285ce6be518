// Open boundaries under the seed paper's variational integrator (issue 32; integrators/variational.cpp
// hold_buffers, docs/open_boundaries.md "With the variational integrator"): buffer particles are held through the
// fixed-point iteration (their chord velocity is prescribed, Tafuni et al. 2018 sec. 3.1), particles are created and
// removed after the step is accepted.
//  - Plane Poiseuille flow with an inlet and an outlet (pipelines/open/channel_poiseuille_variational.json:
//    integrator.type "variational", alpha 0.5): u = 6 U y (H - y) / H^2 and dp/dx = -12 mu U / H^2 (e.g. White,
//    Viscous Fluid Flow, sec. 3-2), against the same scene under symplectic_euler in the same test; mass balance
//    closed to round-off; the fixed point converges every step.
//  - 1 and 2 threads bitwise, a checkpoint restart bitwise (the short fast channel of test_open_boundaries).
//  - Momentum: the fluid's momentum changes only by what crosses the interfaces and by the forces of the walls
//    and of the held buffer particles on it (the fluid-fluid pair forces cancel exactly in the variational step).
#include <gtest/gtest.h>

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "io/checkpoint.hpp"
#include "scene/scene.hpp"
#include "sim/open_boundaries.hpp"
#include "sim/restart.hpp"
#include "sim/simulation.hpp"
#include "open_bitwise_support.hpp"
#include "test_support.hpp"

using namespace varsph;

namespace {

// the fast tier at dx 0.1 (10 rows across H); the validation binary at the scene's dx 0.05
#ifdef VARSPH_OPEN_VARIATIONAL_VALIDATION
constexpr double kDx = 0.05;
#else
constexpr double kDx = 0.1;
#endif
constexpr double kU = 0.1, kH = 1.0, kL = 1.5;

// The steady state is measured as a mean over samples every 0.1 s for t in [1, 2] s (11 samples over about three
// periods 4 L / c0 = 0.3-0.4 s of the channel's acoustic mode): an inflow switched on at full speed leaves an
// acoustic ringing of 1-2 % of u_max in the channel at t = 2 s (docs/open_boundaries.md "Pressure level and
// start-up"), which the variational scheme damps less than the explicit ones, so the value at one instant (the
// metric of test_open_poiseuille) measures the ringing's phase as much as the profile.
struct Measured {
  double profile_error = 0;  // max over rows |<u> - u_exact| / u_max, fluid in the middle third, <> the mean over samples
  double dpdx = 0;           // mean of the least-squares slopes of p(x), fluid 0.3 m from the ends [Pa/m]
  double profile_end = 0, dpdx_end = 0;  // the same at t = 2 s alone
  double balance = 0;        // |mass_in - mass_out - (M - M0)| / M0
  long created = 0, removed = 0;
  int max_iterations = 0;
  long steps = 0;
  double seconds = 0;        // wall time of the run (printed, never asserted)
};

// pipelines/open/channel_poiseuille_variational.json at dx kDx; another integrator in its place for the comparison
scene::Scene poiseuille(const std::string& integrator) {
  std::vector<std::string> sets = {"particles.spacing=" + std::to_string(kDx)};
  if (kDx > 0.05)  // zones and walls 4 spacings deep (the Gaussian's support is 3.6 dx), the domain around them
    for (const char* set : {"open_boundaries.0.min=[-0.4, 0.0]", "open_boundaries.1.max=[1.9, 1.0]", "bodies.1.min=[-0.4, 0.0]",
                            "bodies.1.max=[1.9, 1.0]", "domain.min=[-0.9, -0.9]", "domain.max=[2.4, 1.9]"})
      sets.emplace_back(set);
  if (integrator != "variational") sets.push_back("integrator={\"type\": \"" + integrator + "\", \"cfl\": 0.2}");
  return scene::parse_scene(test::source_dir() / "pipelines/open/channel_poiseuille_variational.json", sets);
}

// the rows' mean u (fluid in the middle third) and the slope of p(x) now
void sample(Simulation<2>& sim, std::vector<double>& u_rows, double& dpdx) {
  const auto& f = sim.fields();
  const auto& zone = sim.store().get<std::int32_t>("open_zone");
  const int rows = int(u_rows.size());
  std::vector<double> sum(std::size_t(rows), 0.0), cnt(std::size_t(rows), 0.0);
  double sx = 0, sp = 0, sxx = 0, sxp = 0, n = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.kind[i] != 0 || zone[i] >= 0) continue;
    const double x = f.x[i][0], y = f.x[i][1];
    if (x >= kL / 3 && x <= 2 * kL / 3) {
      const int r = std::clamp(int(std::floor(y / kDx)), 0, rows - 1);
      sum[std::size_t(r)] += f.v[i][0];
      cnt[std::size_t(r)] += 1;
    }
    if (x >= 0.3 && x <= kL - 0.3) {
      const double p = f.p[i];
      sx += x, sp += p, sxx += x * x, sxp += x * p, n += 1;
    }
  }
  for (int r = 0; r < rows; ++r) u_rows[std::size_t(r)] = cnt[std::size_t(r)] > 0 ? sum[std::size_t(r)] / cnt[std::size_t(r)] : 0;
  dpdx = (n * sxp - sx * sp) / (n * sxx - sx * sx);
}

double profile_error(const std::vector<double>& u_rows) {
  double e = 0;
  for (std::size_t r = 0; r < u_rows.size(); ++r) {
    const double y = (double(r) + 0.5) * kDx;
    e = std::max(e, std::abs(u_rows[r] - 6 * kU * y * (kH - y) / (kH * kH)) / (1.5 * kU));
  }
  return e;
}

Measured run_poiseuille(const std::string& integrator) {
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);  // a few hundred particles: one thread (the bits do not depend on it)
  const auto t0 = std::chrono::steady_clock::now();
  const scene::Scene s = poiseuille(integrator);
  Simulation<2> sim(s);
  Measured m;
  const std::size_t rows = std::size_t(std::lround(kH / kDx));
  std::vector<double> u(rows), u_mean(rows, 0.0);
  double dpdx = 0, samples = 0;
  int next = 10;  // the next sample at t = next / 10 s
  while (sim.time() < s.t_end - 0.5 * sim.dt()) {
    const StepReport& r = sim.advance();
    m.max_iterations = std::max(m.max_iterations, r.iterations);
    if (next <= 20 && sim.time() >= 0.1 * next - 0.5 * sim.dt()) {
      sample(sim, u, dpdx);
      for (std::size_t k = 0; k < rows; ++k) u_mean[k] += u[k];
      m.dpdx += dpdx;
      samples += 1;
      ++next;
    }
  }
  for (auto& x : u_mean) x /= samples;
  m.dpdx /= samples;
  m.profile_error = profile_error(u_mean);
  sample(sim, u, m.dpdx_end);
  m.profile_end = profile_error(u);
  m.steps = sim.step();
  const auto& fl = sim.flow();
  m.balance = std::abs(fl.mass_in - fl.mass_out() - (sim.fluid_mass() - fl.mass0)) / fl.mass0;
  m.created = fl.created;
  m.removed = fl.removed_outlet;
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  omp_set_num_threads(threads);
  EXPECT_EQ(samples, 11);
  return m;
}

#ifndef VARSPH_OPEN_VARIATIONAL_VALIDATION
// The short coarse channel of test_open_boundaries (dx 0.1, uniform inflow 1 m/s, free-slip dummy walls, fixed dt)
// under the variational integrator: particles cross both interfaces within a few hundred steps.
nlohmann::json channel_json() {
  return nlohmann::json::parse(R"({
    "name": "open_channel_variational", "setup": "paper", "dimension": 2,
    "domain": {"min": [-0.6, -0.6], "max": [1.6, 1.6]},
    "particles": {"spacing": 0.1},
    "kernel": {"type": "wendland_c2", "h_over_dx": 1.3},
    "fluid": {"rho0": 1000.0, "c0": 20.0},
    "bodies": [
      {"kind": "fluid", "shape": "box", "min": [0.0, 0.0], "max": [1.0, 1.0]},
      {"kind": "boundary", "shape": "tank", "min": [-0.3, 0.0], "max": [1.3, 1.0], "layers": 3, "open": [true, true, false, false]}
    ],
    "open_boundaries": [
      {"name": "in", "kind": "inlet", "min": [-0.3, 0.0], "max": [0.0, 1.0], "direction": [1.0, 0.0],
       "velocity": {"profile": "uniform", "value": 1.0}},
      {"name": "out", "kind": "outlet", "min": [1.0, 0.0], "max": [1.3, 1.0], "direction": [-1.0, 0.0]}
    ],
    "physics": {"density": "continuity", "laminar_viscosity": {"nu": 0.01}},
    "boundary": {"model": "dummy_adami", "slip": "free_slip"},
    "integrator": {"type": "variational", "alpha": 0.5, "dt": 0.002},
    "time": {"end": 1.0}
  })");
}

scene::Scene channel(const std::vector<std::string>& sets = {}) {
  return scene::parse_scene_json(channel_json(), "open_channel_variational.json", sets);
}

// the state that must come out bitwise equal (tests/support/open_bitwise_support.hpp)
const std::set<std::string> kState = {"position", "velocity", "density", "pressure", "mass", "id", "kind",
                                       "open_zone", "variational_a2"};

#endif

}  // namespace

TEST(OpenVariational, PoiseuilleProfileAndPressureDropAgainstSymplecticEuler) {
  const double mu = 1000.0 * 1.0;  // rho0 nu of the scene
  const double exact = -12 * mu * kU / (kH * kH);
  const Measured v = run_poiseuille("variational");
  const Measured e = run_poiseuille("symplectic_euler");
  for (const auto& [name, m] : {std::pair{"variational", v}, std::pair{"symplectic_euler", e}})
    std::printf("open Poiseuille dx %.3g, %s: %ld steps (max %d iterations, %.1f s), mean over t in [1, 2] s: profile "
                "error %.3f %% of u_max, dp/dx %.2f Pa/m (%.3f %%); at t = 2 s: %.3f %%, %.2f Pa/m (%.3f %%); mass "
                "balance %.2g of M0, created %ld, removed %ld\n",
                kDx, name, m.steps, m.max_iterations, m.seconds, 100 * m.profile_error, m.dpdx,
                100 * std::abs(m.dpdx / exact - 1), 100 * m.profile_end, m.dpdx_end, 100 * std::abs(m.dpdx_end / exact - 1),
                m.balance, m.created, m.removed);
#ifdef VARSPH_OPEN_VARIATIONAL_VALIDATION
  // the issue's goals at dx 0.05: profile within 1 % of u_max, pressure drop within 2 %
  EXPECT_LT(v.profile_error, 0.01);
  EXPECT_LT(std::abs(v.dpdx / exact - 1), 0.02);
#else
  // dx 0.1 (10 rows): what the explicit scheme meets at this resolution, with a margin
  // (measured 2026-11-28: variational 1.46 % and 1.75 %, symplectic_euler 1.37 % and 2.25 %)
  EXPECT_LT(v.profile_error, 0.02);
  EXPECT_LT(std::abs(v.dpdx / exact - 1), 0.04);
#endif
  // the implicit scheme and the explicit one on the same steady flow: well within the discretisation error
  // (measured: 6.0 Pa/m and 0.10 % of u_max apart at dx 0.1, 4.4 Pa/m and 0.07 % at dx 0.05)
  EXPECT_LT(std::abs(v.dpdx - e.dpdx), 0.01 * std::abs(exact));
  EXPECT_LT(std::abs(v.profile_error - e.profile_error), 0.002);
  EXPECT_LT(v.balance, 1e-12);
  EXPECT_GT(v.created, 0);
  EXPECT_GT(v.removed, 0);
  EXPECT_GT(v.max_iterations, 1);  // the fixed point ran (alpha 0.5 with viscosity is implicit)
}

#ifndef VARSPH_OPEN_VARIATIONAL_VALIDATION
TEST(OpenVariational, FlowThroughHoldsBuffersAndClosesTheMassBalance) {
  Simulation<2> sim(channel());
  const std::int64_t first_new = sim.next_id();
  const auto& zone0 = sim.store().get<std::int32_t>("open_zone");
  int iterations = 0;
  for (int s = 0; s < 250; ++s) {  // 0.5 s: every inlet column has fed the fluid
    // the inlet buffer particles move with the prescribed 1 m/s: x_{k+1} = x_k + dt v0 exactly
    std::vector<std::pair<std::int64_t, double>> before;
    const auto& f = sim.fields();
    for (std::size_t i = 0; i < sim.size(); ++i)
      if (zone0[i] == 0) before.emplace_back(f.id[i], double(f.x[i][0]));
    iterations = std::max(iterations, sim.advance().iterations);
    const auto& zone = sim.store().get<std::int32_t>("open_zone");
    std::size_t checked = 0;
    for (std::size_t i = 0; i < sim.size(); ++i) {
      const auto it = std::find_if(before.begin(), before.end(), [&](const auto& b) { return b.first == f.id[i]; });
      if (it == before.end()) continue;
      ++checked;
      EXPECT_EQ(double(f.x[i][0]), double(Real(it->second) + Real(0.002) * Real(1.0))) << "id " << f.id[i];
      if (zone[i] == 0) {
        EXPECT_EQ(double(f.v[i][0]), 1.0);
      }
    }
    ASSERT_EQ(checked, before.size());
  }
  EXPECT_GT(iterations, 1);
  const auto& fl = sim.flow();
  EXPECT_GE(fl.created, 40);
  EXPECT_GT(fl.removed_outlet, 0);
  EXPECT_EQ(sim.next_id(), first_new + fl.created);
  std::set<std::int64_t> ids;
  for (std::size_t i = 0; i < sim.size(); ++i) ids.insert(sim.fields().id[i]);
  EXPECT_EQ(ids.size(), sim.size());
  const double m = sim.fluid_mass();
  EXPECT_LE(std::abs(fl.mass_in - fl.mass_out() - (m - fl.mass0)), 1e-12 * fl.mass0);
  // the inflow of 1 m/s over H = 1 m for 0.5 s: rho0 U H t = 500 kg/m, within a column per lattice column
  EXPECT_NEAR(fl.mass_in, 500.0, 10 * 10.0);
  const auto& zone = sim.store().get<std::int32_t>("open_zone");
  std::size_t in = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) in += zone[i] == 0;
  EXPECT_EQ(in, 30u);  // every inlet column keeps its 3 lattice particles
}

TEST(OpenVariational, ThreadsGiveTheSameBits) { test::expect_open_threads_bitwise(channel(), kState); }

TEST(OpenVariational, RestartFromACheckpointIsBitwise) {
  test::expect_open_restart_bitwise(channel(), kState, "open_var_restart");
}

TEST(OpenVariational, MultiStageSchemesAreStillRefusedNamingTheKey) {
  for (const char* type : {"rk4", "predictor_corrector"}) {
    std::string e;
    try {
      Simulation<2> sim(channel({std::string("integrator={\"type\": \"") + type + "\", \"dt\": 0.002}"}));
    } catch (const InputError& x) {
      e = x.what();
    }
    EXPECT_NE(e.find("integrator.type"), std::string::npos) << e;
    EXPECT_NE(e.find("variational"), std::string::npos) << e;  // names what does run
  }
}
#endif
