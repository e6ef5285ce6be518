// The variational integrator (seed eq. 63-65, Algorithm 1): equivalence with Verlet at the explicit
// ends, momentum conservation (eq. 39) for every alpha (also with the iteration stopped early), angular
// momentum of a free cluster, the skin that keeps the neighbour lists valid at the midpoints, the reuse
// of a2, and the failure handling (fail / halve_dt).
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "../support/real_tolerance.hpp"
#include "core/errors.hpp"
#include "physics/pair_loop.hpp"
#include "sim/diagnostics.hpp"
#include "test_support.hpp"
#include "variational_cases.hpp"

using namespace varsph;
using test::lattice_scene;
using test::make_scene;

namespace {

struct OneThread : ::testing::Environment {
  void SetUp() override { omp_set_num_threads(1); }
};
const auto* const kEnv = ::testing::AddGlobalTestEnvironment(new OneThread);

scene::Scene dam_break(const std::vector<std::string>& overrides) {
  return scene::parse_scene(test::source_dir() / "pipelines" / "dam_break_2d_paper.json", overrides);
}

// max |x_a - x_b| over particles matched by id, relative to the extent of the fluid
double relative_difference(const Simulation<2>& a, const Simulation<2>& b) {
  const auto pa = test::positions_by_id(a), pb = test::positions_by_id(b);
  double d = 0, ext = 0;
  for (const auto& [id, x] : pa) {
    d = std::max(d, double((x - pb.at(id)).norm()));
    ext = std::max(ext, double(x.norm()));
  }
  return d / ext;
}

}  // namespace

TEST(Variational, Alpha1IsTheVerletCodePathOnTheDamBreak) {
  Simulation<2> verlet(dam_break({}));
  Simulation<2> var(dam_break({"integrator.type=\"variational\"", "integrator.alpha=1"}));
  ASSERT_STREQ(var.integrator().name(), "variational");
  EXPECT_TRUE(test::variational_of(var)->explicit_scheme());
  for (int k = 0; k < 1000; ++k) {
    verlet.advance();
    var.advance();
  }
  EXPECT_LE(relative_difference(verlet, var), 1e-9);  // bitwise in fact: the same verlet_step()
  EXPECT_EQ(relative_difference(verlet, var), 0.0);
}

TEST(Variational, Alpha0WithSummationAndNoViscosityIsExplicitAndAgreesWithVerlet) {
  // the paper's dam break with summation density and without the viscosity term
  auto j = nlohmann::json::parse(test::read_text(test::source_dir() / "pipelines" / "dam_break_2d_paper.json"));
  j["physics"].erase("artificial_viscosity");
  j["physics"]["density"] = "summation";
  Simulation<2> verlet(make_scene(j));
  j["integrator"]["type"] = "variational";
  j["integrator"]["alpha"] = 0.0;
  Simulation<2> var(make_scene(j));
  ASSERT_TRUE(test::variational_of(var)->explicit_scheme());
  for (int k = 0; k < 1000; ++k) {
    verlet.advance();
    const StepReport r = var.advance();
    ASSERT_EQ(r.iterations, 1);
  }
  // bitwise in fact (Gamma_k stays in the a1 pass at alpha = 0); this inviscid summation flow amplifies
  // rounding differences e-fold every ~17 steps, so anything short of that would not hold over 1000 steps
  const double d = relative_difference(verlet, var);
  std::printf("alpha = 0 (explicit) vs verlet after 1000 steps: relative difference %.3g\n", d);
  EXPECT_LE(d, 1e-9);
}

TEST(Variational, Alpha0WithViscosityOrContinuityIsImplicit) {
  for (const auto& [density, visc] : {std::pair{"continuity", 0.0}, std::pair{"summation", 0.1}}) {
    Simulation<2> sim(make_scene(lattice_scene(16, 0.3, true, 0.0, "variational", density, 2e-4, visc)));
    auto* vi = test::variational_of(sim);
    EXPECT_FALSE(vi->explicit_scheme()) << density << " visc " << visc;
    EXPECT_TRUE(vi->implicit());
    const StepReport r = sim.advance();
    EXPECT_GE(r.iterations, 2);
    EXPECT_LE(r.residual, 1e-6 * 0.01);
  }
}

// eq. (39): sum_i m_i a_i = 0 for every iterate, so P is conserved to rounding, for every alpha and
// also when the fixed-point iteration is stopped after one or two iterations.
class MomentumByAlpha : public ::testing::TestWithParam<std::tuple<double, int>> {};

TEST_P(MomentumByAlpha, PeriodicBoxConservesLinearMomentum) {
  const auto [alpha, fixed] = GetParam();
  Simulation<2> sim(make_scene(lattice_scene(16, 0.5, true, alpha, alpha == 1 ? "verlet" : "variational",
                                             "continuity", 2e-4)));
  if (fixed > 0) test::variational_of(sim)->set_fixed_iterations(fixed);
  auto momentum = [&](double& scale) {
    Eigen::Vector2d P = Eigen::Vector2d::Zero();
    scale = 0;
    for (std::size_t i = 0; i < sim.size(); ++i) {
      P += (sim.fields().mass[i] * sim.fields().v[i]).cast<double>();
      scale += double(sim.fields().mass[i] * sim.fields().v[i].norm());
    }
    return P;
  };
  double scale0;
  const Eigen::Vector2d P0 = momentum(scale0);
  double worst = 0;
  long wraps = 0;
  for (int k = 0; k < 2000; ++k) {
    const auto before = test::positions_by_id(sim);
    sim.advance();
    for (std::size_t i = 0; i < sim.size(); ++i)  // a jump of more than half the box: a periodic wrap
      wraps += (sim.fields().x[i] - before.at(sim.fields().id[i])).norm() > 0.08;
    double scale;
    const Eigen::Vector2d P = momentum(scale);
    worst = std::max(worst, (P - P0).norm() / scale);
    ASSERT_EQ(check_health(sim), "") << "step " << k;
  }
  std::printf("alpha %.2f fixed iterations %d: max |P - P0| / sum m|v| = %.3g (%ld periodic wraps)\n", alpha,
              fixed, worst, wraps);
  EXPECT_LE(worst, test::real_tol(1e-12, 64));  // float: rounding of 2000 steps
  // particles crossed the periodic boundaries (q_{k-1} is implicit in v_{k-1/2}, never wrapped apart)
  EXPECT_GT(wraps, 100);
}

INSTANTIATE_TEST_SUITE_P(Alphas, MomentumByAlpha,
                         ::testing::Values(std::tuple{0.0, 0}, std::tuple{0.25, 0}, std::tuple{0.5, 0},
                                           std::tuple{0.75, 0}, std::tuple{1.0, 0}, std::tuple{0.0, 1},
                                           std::tuple{0.5, 1}, std::tuple{0.75, 2}));

// Central pair forces (radial kernel gradient, Monaghan viscosity along x_ij): the discrete momentum
// map J_k = sum_i q_k^i x m_i (v_{k-1/2}^i + alpha dt a2^i) of the generalized midpoint rule is
// conserved exactly (a2 of step k+1 is the a1 of step k, whose pair forces are central in the
// midpoint configuration); sum q x m v itself only oscillates by O(dt).
class AngularByAlpha : public ::testing::TestWithParam<double> {};

TEST_P(AngularByAlpha, FreeClusterConservesAngularMomentum) {
  const double alpha = GetParam();
  const double dt = 2e-4;
  Simulation<2> sim(make_scene(lattice_scene(12, 0.2, false, alpha, alpha == 1 ? "verlet" : "variational",
                                             "continuity", dt, 0.1, 11, 5.0),
                               // float: the residual stalls near 2e-11 m (float positions of O(0.1) m); 1e-7 gives 1e-9 m here
                               {test::kRealIsDouble ? "integrator.fixed_point.tolerance=1e-12"
                                                    : "integrator.fixed_point.tolerance=1e-7"}));
  auto* vi = test::variational_of(sim);
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  double M = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    c += double(sim.fields().mass[i]) * sim.fields().x[i].cast<double>();
    M += sim.fields().mass[i];
  }
  c /= M;
  auto J = [&](double& scale) {
    double j = 0;
    scale = 0;
    for (std::size_t i = 0; i < sim.size(); ++i) {
      const Eigen::Vector2d r = sim.fields().x[i].cast<double>() - c;
      Eigen::Vector2d p = (sim.fields().mass[i] * sim.fields().v[i]).cast<double>();
      if (vi) p += alpha * dt * double(sim.fields().mass[i]) * vi->cached_a2()[i].cast<double>();
      j += r.x() * p.y() - r.y() * p.x();
      scale += r.norm() * p.norm();
    }
    return j;
  };
  double s0;
  const double J0 = J(s0);
  double worst = 0;
  for (int k = 0; k < 2000; ++k) {
    sim.advance();
    double s;
    worst = std::max(worst, std::abs(J(s) - J0) / s);
  }
  std::printf("alpha %.2f: max |J - J0| / sum |r| |p| = %.3g (J0 = %.4g)\n", alpha, worst, J0);
  EXPECT_LE(worst, test::real_tol(1e-12, 64));  // float: rounding of 2000 steps
}

INSTANTIATE_TEST_SUITE_P(Alphas, AngularByAlpha, ::testing::Values(0.0, 0.25, 0.5, 0.75, 1.0));

namespace {
// counts, per particle, the neighbours the grid hands to a pass for configuration x
struct CountPass {
  std::vector<int>& out;
  bool active(std::size_t) const { return true; }
  int begin(std::size_t) const { return 0; }
  void pair(int& acc, std::size_t, std::size_t, const Vec<2>&, Real) const { ++acc; }
  void end(std::size_t i, int acc) const { out[i] = acc; }
};
}  // namespace

TEST(Variational, SkinKeepsNeighbourListsValidAtEveryMidpoint) {
  // fast particles (dt |v| ~ 0.3 dx): the 5 % starting skin is too thin and must be widened
  Simulation<2> sim(make_scene(lattice_scene(20, 15.0, true, 0.5, "variational", "continuity", 2e-4, 0.1)));
  auto* vi = test::variational_of(sim);
  vi->set_fixed_iterations(3);
  const Real rc = sim.rates().support();
  const Real skin0 = Real(0.05) * rc;  // the starting skin
  const Real L = 0.2;
  long evaluations = 0, mismatches = 0;
  std::vector<int> grid_count(sim.size()), brute(sim.size());
  vi->on_evaluation = [&](const NeighborGrid<2>& g, std::span<const Vec<2>> x) {
    ++evaluations;
    CountPass pass{grid_count};
    for_each_particle_pairs<2>(g, x, rc, pass);
    for (std::size_t i = 0; i < x.size(); ++i) {
      int c = 0;
      for (std::size_t j = 0; j < x.size(); ++j) {
        if (i == j) continue;
        Vec<2> d = x[i] - x[j];
        for (int a = 0; a < 2; ++a) d[a] -= L * std::round(d[a] / L);  // minimal image
        c += d.squaredNorm() < rc * rc;
      }
      brute[i] = c;
      mismatches += brute[i] != grid_count[i];
    }
  };
  for (int k = 0; k < 10; ++k) sim.advance();
  EXPECT_GT(evaluations, 30);
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(sim.skin(), skin0) << "the skin should have been widened for these speeds";
}

TEST(Variational, ReusedA2MatchesAFreshEvaluationToTheTolerance) {
  for (const char* density : {"summation", "continuity"}) {
    const double dt = 2e-4, alpha = 0.5, tol = 1e-6 * 0.01;
    Simulation<2> sim(make_scene(lattice_scene(16, 0.5, true, alpha, "variational", density, dt, 0.1)));
    auto* vi = test::variational_of(sim);
    std::vector<Vec<2>> fresh;
    double worst = 0;
    for (int k = 0; k < 50; ++k) {
      sim.advance();
      vi->fresh_a2(sim, fresh);
      const auto cached = vi->cached_a2();
      for (std::size_t i = 0; i < sim.size(); ++i)
        worst = std::max(worst, double((cached[i] - fresh[i]).norm()));
    }
    // the position change that a2's difference makes: dt^2 (1 - alpha) |da| <= c r_j <= tol
    const double effect = dt * dt * (1 - alpha) * worst;
    std::printf("%s: max |a2 cached - fresh| = %.3g m/s^2 -> %.3g m in q (tolerance %.3g m)\n", density, worst,
                effect, tol);
    EXPECT_LE(effect, tol);
  }
}

TEST(Variational, NonConvergenceFailsAtTheLastAcceptedStep) {
  // dt 20x past the acoustic limit: the fixed point diverges
  Simulation<2> sim(make_scene(lattice_scene(20, 0.5, true, 0.5, "variational", "continuity", 4e-3)));
  const auto before = test::positions_by_id(sim);
  const double t0 = sim.time();
  const long s0 = sim.step();
  try {
    sim.advance();
    FAIL() << "expected a NumericalError";
  } catch (const NumericalError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("residuals"), std::string::npos) << msg;
    EXPECT_NE(msg.find("step 1"), std::string::npos) << msg;
  }
  EXPECT_EQ(sim.time(), t0);
  EXPECT_EQ(sim.step(), s0);
  EXPECT_EQ(test::positions_by_id(sim), before);
}

TEST(Variational, HalveDtRedoesTheStepAndGrowsBack) {
  Simulation<2> sim(make_scene(lattice_scene(16, 0.5, true, 0.5, "variational", "continuity", 1.6e-3),
                               {"integrator.fixed_point.on_failure=\"halve_dt\""}));
  auto* vi = test::variational_of(sim);
  Eigen::Vector2d P0 = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < sim.size(); ++i) P0 += (sim.fields().mass[i] * sim.fields().v[i]).cast<double>();
  int max_halvings = 0;
  bool grew = false;
  for (int k = 0; k < 400; ++k) {
    const int h = vi->halvings();
    sim.advance();
    max_halvings = std::max(max_halvings, vi->halvings());
    grew |= vi->halvings() < h;
    const double m = std::log2(1.6e-3 / sim.dt());  // dt = scene dt / 2^m
    EXPECT_NEAR(m, std::round(m), 1e-9);
    ASSERT_EQ(check_health(sim), "");
  }
  EXPECT_GT(max_halvings, 0);
  EXPECT_TRUE(grew);
  Eigen::Vector2d P = Eigen::Vector2d::Zero();
  double scale = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    P += (sim.fields().mass[i] * sim.fields().v[i]).cast<double>();
    scale += double(sim.fields().mass[i] * sim.fields().v[i].norm());
  }
  EXPECT_LE((P - P0).norm(), test::real_tol(1e-12, 64) * scale);
  const auto st = vi->save_state();
  EXPECT_TRUE(st.contains("halvings") && st.contains("dt_prev"));
}

TEST(Variational, RunExitsWith3AndKeepsTheLastGoodFrame) {
  const auto dir = test::scratch_dir("variational_fail");
  auto j = lattice_scene(20, 0.5, true, 0.5, "variational", "continuity", 4e-3);
  j["output"] = {{"every", 4e-3}};
  std::ofstream(dir / "diverge.json") << j.dump();
  const auto r = test::run_command(test::varsph_exe().string() + " run " + (dir / "diverge.json").string() +
                                   " -o " + (dir / "run").string() + " --threads 1 --quiet");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("residuals"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("last good frame"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "run" / "frames" / "lattice_000000.vtu"));
}

TEST(Variational, DiagnosticsCarryTheFixedPointColumns) {
  const auto dir = test::scratch_dir("variational_diag");
  auto j = lattice_scene(16, 0.5, true, 0.5, "variational", "continuity", 2e-4);
  j["time"] = {{"end", 0.01}};
  j["output"] = {{"every", 0.005}};
  std::ofstream(dir / "ok.json") << j.dump();
  const auto r = test::run_command(test::varsph_exe().string() + " run " + (dir / "ok.json").string() + " -o " +
                                   (dir / "run").string() + " --threads 1 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string csv = test::read_text(dir / "run" / "diagnostics.csv");
  EXPECT_NE(csv.find("fp_iterations_mean"), std::string::npos);
  // the row of frame 1 has non-empty fixed-point columns
  const auto line1 = csv.substr(csv.find("\n1,"));
  EXPECT_EQ(line1.find(",,"), std::string::npos) << line1.substr(0, 300);
  const auto info = test::run_command(test::varsph_exe().string() + " info " + (dir / "ok.json").string());
  EXPECT_NE(info.output.find("variational bound  dt <"), std::string::npos) << info.output;
}

TEST(Variational, ThreeDimensionalPeriodicBoxConvergesAndConservesMomentum) {
  const int n = 12;
  const double dx = 0.01, L = n * dx;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> N(0.0, 1.0);
  nlohmann::json pts = nlohmann::json::array(), vel = nlohmann::json::array();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        pts.push_back({(i + 0.5) * dx, (j + 0.5) * dx, (k + 0.5) * dx});
        vel.push_back({0.5 * N(rng), 0.5 * N(rng), 0.5 * N(rng)});
      }
  nlohmann::json j = {{"name", "box3"},
                      {"setup", "paper"}, {"dimension", 3},
                      {"domain", {{"min", {0.0, 0.0, 0.0}}, {"max", {L, L, L}}, {"periodic", {true, true, true}}}},
                      {"particles", {{"spacing", dx}}},
                      {"fluid", {{"c0", 10.0}}},
                      {"gravity", {0.0, 0.0, 0.0}},
                      {"bodies", {{{"kind", "fluid"}, {"shape", "points"}, {"points", pts}, {"velocities", vel}}}},
                      {"physics", {{"artificial_viscosity", {{"alpha", 0.1}}}}},
                      {"integrator", {{"type", "variational"}, {"dt", 2e-4}, {"alpha", 0.5}}},
                      {"time", {{"end", 1.0}}}};
  Simulation<3> sim(make_scene(j));
  auto momentum = [&](double& scale) {
    Eigen::Vector3d P = Eigen::Vector3d::Zero();
    scale = 0;
    for (std::size_t i = 0; i < sim.size(); ++i) {
      P += (sim.fields().mass[i] * sim.fields().v[i]).cast<double>();
      scale += double(sim.fields().mass[i] * sim.fields().v[i].norm());
    }
    return P;
  };
  double s0;
  const Eigen::Vector3d P0 = momentum(s0);
  for (int k = 0; k < 40; ++k) {
    const StepReport r = sim.advance();
    ASSERT_LE(r.residual, 1e-6 * dx);
    ASSERT_GE(r.iterations, 2);
    double s;
    const double dP = (momentum(s) - P0).norm();
    ASSERT_LE(dP, test::real_tol(1e-12, 64) * s) << "step " << k;
  }
  EXPECT_GT(sim.last_report().dt_bound, 2e-4);
}
