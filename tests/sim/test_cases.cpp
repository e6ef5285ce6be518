// Whole small cases: hydrostatic tank, the paper's dam break, thread independence, a wall impact.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "../support/real_tolerance.hpp"
#include "core/errors.hpp"
#include "scene/scene.hpp"
#include "sim/diagnostics.hpp"
#include "sim/simulation.hpp"
#include "test_support.hpp"

using namespace varsph;

namespace {

scene::Scene load(const std::string& file, const std::vector<std::string>& overrides = {}) {
  return scene::parse_scene(test::source_dir() / "pipelines" / file, overrides);
}

template <int D>
void run_until(Simulation<D>& sim, double t) {
  while (sim.time() < t - 0.5 * sim.dt()) {
    sim.advance();
    ASSERT_EQ(check_health(sim), "") << "at step " << sim.step();
  }
}

}  // namespace

class HydrostaticTank : public ::testing::TestWithParam<std::string> {};

TEST_P(HydrostaticTank, HoldsStillWithHydrostaticPressure) {
  // pipelines/hydrostatic_2d*.json (dynamic boundary particles; box-built or mesh-built tank), 1 s
  Simulation<2> sim(load(GetParam(), {"time.end=1.0"}));
  run_until(sim, 1.0);
  const double rho0 = 1000, g = 9.81, H = 0.3;
  const auto& f = sim.fields();
  // pressure averaged in 10 depth bands against rho0 g (H - y): within 2 % of rho0 g H everywhere
  double sum[10] = {}, ysum[10] = {};
  int cnt[10] = {};
  double vmax = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.kind[i] != 0) continue;
    const double x = f.x[i][0], y = f.x[i][1];
    EXPECT_TRUE(x > 0 && x < 0.4 && y > 0 && y < 0.5) << "particle " << f.id[i] << " left the tank";
    vmax = std::max(vmax, double(f.v[i].norm()));
    const int b = std::clamp(int(y / (H / 10)), 0, 9);
    sum[b] += f.p[i];
    ysum[b] += y;
    ++cnt[b];
  }
  for (int b = 0; b < 10; ++b) {
    ASSERT_GT(cnt[b], 0);
    const double y = ysum[b] / cnt[b], p = sum[b] / cnt[b];
    EXPECT_NEAR(p, rho0 * g * (H - y), 0.02 * rho0 * g * H) << "band " << b << " at y = " << y;
  }
  EXPECT_LT(vmax, 0.01 * std::sqrt(g * H));
}
#ifdef VARSPH_TEST_HAVE_GEOMETRY  // the mesh-built tank and mesh errors need the geometry module
INSTANTIATE_TEST_SUITE_P(Cases, HydrostaticTank,
                         ::testing::Values("hydrostatic_2d.json", "hydrostatic_2d_mesh.json"),
                         [](const auto& info) { return info.param.find("mesh") != std::string::npos ? "MeshTank" : "BoxTank"; });

TEST(Cases, MeshBodyErrorsAreInputErrorsNamingTheBodyAndFile) {
  const auto dir = test::scratch_dir("mesh_errors");
  auto j = nlohmann::json::parse(test::read_text(test::source_dir() / "pipelines" / "hydrostatic_2d_mesh.json"));
  j["bodies"][1]["mesh"] = (test::source_dir() / "geometry" / "meshes" / "no_such_tank.poly2d").string();
  std::ofstream(dir / "missing.json") << j.dump();
  auto r = test::run_command(test::varsph_exe().string() + " sample " + (dir / "missing.json").string() + " -o " +
                             (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bodies.1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("no_such_tank.poly2d"), std::string::npos) << r.output;
}
#else
INSTANTIATE_TEST_SUITE_P(Cases, HydrostaticTank, ::testing::Values("hydrostatic_2d.json"),
                         [](const auto&) { return std::string("BoxTank"); });

TEST(Cases, MeshBodiesWithoutTheGeometryModuleAreInputErrorsNamingTheBody) {
  // a build without CGAL refuses mesh bodies by design (src/sim/mesh_bodies.cpp): exit 2, not a crash
  const auto dir = test::scratch_dir("mesh_without_geometry");
  auto r = test::run_command(test::varsph_exe().string() + " sample " +
                             (test::source_dir() / "pipelines" / "hydrostatic_2d_mesh.json").string() + " -o " +
                             (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bodies.1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("need the geometry module"), std::string::npos) << r.output;
}
#endif

TEST(Cases, FluidBodyInsideABoundaryBlockIsAnInputError) {
  // a fluid body entirely inside a boundary block: every fluid particle is removed -> exit 2
  const auto dir = test::scratch_dir("fluid_in_wall");
  auto k = nlohmann::json::parse(test::read_text(test::source_dir() / "pipelines" / "hydrostatic_2d.json"));
  k["bodies"][1] = {{"kind", "boundary"}, {"shape", "box"}, {"min", {-0.01, -0.01}}, {"max", {0.41, 0.31}}, {"layers", 16}};
  std::ofstream(dir / "overlap.json") << k.dump();
  const auto r = test::run_command(test::varsph_exe().string() + " sample " + (dir / "overlap.json").string() +
                                   " -o " + (dir / "out2").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("overlaps a boundary body"), std::string::npos) << r.output;
}

TEST(Cases, PaperDamBreakRunsAndTheSurgeFrontAdvances) {
  Simulation<2> sim(load("dam_break_2d_paper.json"));
  const auto front = [&] {
    double xf = 0;
    for (std::size_t i = 0; i < sim.size(); ++i)
      if (sim.fields().kind[i] == 0) xf = std::max(xf, double(sim.fields().x[i][0]));
    return xf;
  };
  double last = front();
  EXPECT_NEAR(last, 0.1425, test::real_tol(1e-9, 4, 0.1425));
  for (double t : {0.1, 0.2, 0.3}) {
    run_until(sim, t);
    const double xf = front();
    EXPECT_GT(xf, last + 0.02) << "front did not advance by t = " << t;
    last = xf;
  }
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (sim.fields().kind[i] != 0) continue;
    const auto& x = sim.fields().x[i];
    EXPECT_TRUE(x.allFinite());
    EXPECT_TRUE(x[0] > 0 && x[0] < 0.58 && x[1] > 0 && x[1] < 0.6) << "particle outside the tank";
  }
  // Ritter's ideal dam-break front speed is 2 sqrt(g H) = 3.4 m/s; the real front is slower
  EXPECT_LT(last, 0.1425 + 0.3 * 2 * std::sqrt(9.8 * 0.29));
}

TEST(Cases, OneAndTwoThreadsGiveBitwiseIdenticalResults) {
  std::vector<std::vector<std::byte>> results;
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    Simulation<2> sim(load("dam_break_2d_paper.json"));
    for (int k = 0; k < 100; ++k) sim.advance();
    std::vector<std::byte> bytes;
    for (const auto& field : sim.store().fields()) {
      const auto* p = static_cast<const std::byte*>(field->raw());
      bytes.insert(bytes.end(), p, p + field->bytes_per_particle() * field->size());
    }
    results.push_back(bytes);
  }
  omp_set_num_threads(omp_get_num_procs());
  ASSERT_EQ(results[0].size(), results[1].size());
  EXPECT_EQ(std::memcmp(results[0].data(), results[1].data(), results[0].size()), 0);
}

TEST(Cases, ParticleThrownAtTheWallAtDamBreakSpeedDoesNotPassIt) {
  // PAPER-NOTES.md: eq. (58) with D = 2 g H stops a particle at sqrt(2 g H) = 2.4 m/s
  auto j = nlohmann::json::parse(R"({
    "name": "impact", "setup": "paper", "dimension": 2,
    "domain": {"min": [-0.05, -0.05], "max": [0.2, 0.2]},
    "particles": {"spacing": 0.005},
    "gravity": [0, -9.8],
    "fluid": {"c0": 24},
    "bodies": [{"kind": "fluid", "shape": "points", "points": [[0.05, 0.0125]], "velocities": [[0, -2.4]]},
               {"kind": "boundary", "shape": "tank", "min": [0, 0], "max": [0.1, 0.1], "layers": 1}],
    "boundary": {"repulsive": {"D": 5.684}},
    "integrator": {"dt": 1e-5}, "time": {"end": 0.03}
  })");
  Simulation<2> sim(scene::parse_scene_json(j, "impact.json"));
  double lowest = 1;
  while (sim.time() < 0.03) {
    sim.advance();
    for (std::size_t i = 0; i < sim.size(); ++i)
      if (sim.fields().kind[i] == 0) lowest = std::min(lowest, double(sim.fields().x[i][1]));
  }
  EXPECT_GT(lowest, -0.0025 + 0.001) << "the particle reached the wall particles' row";
  EXPECT_LT(lowest, 0.0025) << "the particle should come close to the wall";
}

TEST(Cases, GivenInitialPressuresAndBackgroundPressureAreHonoured) {
  // points with initial pressures: rho from the inverse of eq. (11); p = B((rho/rho0)^7 - 1) + p_b
  auto j = nlohmann::json::parse(R"({
    "name": "pressures", "setup": "paper", "dimension": 2,
    "domain": {"min": [-1, -1], "max": [1, 1]},
    "particles": {"spacing": 0.1},
    "fluid": {"c0": 10, "background_pressure": 50},
    "bodies": [{"kind": "fluid", "shape": "points", "points": [[0, 0], [0.5, 0.5]], "pressures": [100, -20]}],
    "integrator": {"dt": 1e-4}, "time": {"end": 0.001}
  })");
  Simulation<2> sim(scene::parse_scene_json(j, "p.json"));
  for (std::size_t i = 0; i < sim.size(); ++i) {
    const double given = sim.fields().id[i] == 0 ? 100.0 : -20.0;
    EXPECT_NEAR(double(sim.fields().p[i]), given + 50.0, test::real_tol(1e-9 * 1000.0, 64, 1000.0));
  }
  j["bodies"][0]["pressures"] = {1.0};
  EXPECT_THROW(scene::parse_scene_json(j, "p.json"), InputError);
}
