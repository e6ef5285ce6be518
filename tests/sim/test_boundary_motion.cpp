// Prescribed boundary motion: particles follow the law exactly, velocities are its derivative, and the
// fluid feels the moving wall through the wall model.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../support/real_tolerance.hpp"
#include "core/errors.hpp"
#include "scene/scene.hpp"
#include "sim/simulation.hpp"

using namespace varsph;
using nlohmann::json;

namespace {

json tank_scene(const json& motion) {
  json j = json::parse(R"({
    "name": "moving", "setup": "paper", "dimension": 2,
    "domain": {"min": [-0.2, -0.2], "max": [0.6, 0.5]},
    "particles": {"spacing": 0.01},
    "gravity": [0, -9.81],
    "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0], "max": [0.3, 0.1], "initial_pressure": "hydrostatic"},
               {"kind": "boundary", "shape": "tank", "min": [0, 0], "max": [0.3, 0.2], "layers": 4}],
    "physics": {"artificial_viscosity": {"alpha": 0.1}},
    "boundary": {"model": "dynamic"},
    "integrator": {"dt": 5e-5}, "time": {"end": 1}
  })");
  j["bodies"][1]["motion"] = motion;
  return j;
}

}  // namespace

TEST(BoundaryMotion, OscillatingTankFollowsTheLawAndSetsTheFluidSloshing) {
  const double A = 0.01, f = 2.0;
  Simulation<2> sim(scene::parse_scene_json(tank_scene({{"type", "oscillation"}, {"amplitude", {A, 0}}, {"frequency", f}}), "osc.json"));
  const auto& fl = sim.fields();
  auto& x0 = sim.store().get<Vec<2>>("reference_position");
  for (int k = 0; k < 1000; ++k) sim.advance();  // t = 0.05 s
  // the walls are set at the start of each step: after advance() they sit at t = time() (sort_and_bin)
  const double t = sim.time();
  double px = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (fl.kind[i] == 0) {
      px += double(fl.mass[i] * fl.v[i][0]);
      continue;
    }
    const double ex = double(x0[i][0]) + A * std::sin(2 * std::numbers::pi * f * t);
    EXPECT_NEAR(double(fl.x[i][0]), ex, test::real_tol(1e-12, 8));
    EXPECT_NEAR(double(fl.x[i][1]), double(x0[i][1]), test::real_tol(1e-15, 8));
  }
  // the tank moved right with speed ~A 2 pi f: the fluid has been pushed along
  EXPECT_GT(px, 0.05 * 0.3 * 0.1 * 1000 * A * 2 * std::numbers::pi * f);
}

TEST(BoundaryMotion, RotationKeepsDistancesAndGivesRigidVelocities) {
  json j = tank_scene(nullptr);
  j["bodies"][1]["motion"] = nullptr;
  j["bodies"].push_back({{"kind", "boundary"}, {"shape", "box"}, {"min", {0.1, 0.12}}, {"max", {0.2, 0.14}},
                         {"layers", 1}, {"motion", {{"type", "rotation"}, {"center", {0.15, 0.13}}, {"omega", 3.0}}}});
  Simulation<2> sim(scene::parse_scene_json(j, "rot.json"));
  const auto& fl = sim.fields();
  auto& x0 = sim.store().get<Vec<2>>("reference_position");
  for (int k = 0; k < 200; ++k) sim.advance();
  const Vec<2> c(Real(0.15), Real(0.13));
  const double th = 3.0 * sim.time();
  int checked = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (fl.body[i] != 2) continue;
    ++checked;
    const Vec<2> r0 = x0[i] - c, r = fl.x[i] - c;
    EXPECT_NEAR(double(r.norm()), double(r0.norm()), test::real_tol(1e-12, 8));
    EXPECT_NEAR(double(r[0]), std::cos(th) * double(r0[0]) - std::sin(th) * double(r0[1]), test::real_tol(1e-12, 8));
    // v = omega x r
    EXPECT_NEAR(double(fl.v[i][0]), -3.0 * double(r[1]), test::real_tol(1e-9, 16));
    EXPECT_NEAR(double(fl.v[i][1]), 3.0 * double(r[0]), test::real_tol(1e-9, 16));
  }
  EXPECT_GT(checked, 10);
}

TEST(BoundaryMotion, TranslationStopsAtItsEndAndBadKeysAreNamed) {
  Simulation<2> sim(scene::parse_scene_json(
      tank_scene({{"type", "translation"}, {"velocity", {0.2, 0}}, {"end", 0.01}}), "tr.json"));
  for (int k = 0; k < 400; ++k) sim.advance();  // t = 0.02 s
  const auto& fl = sim.fields();
  auto& x0 = sim.store().get<Vec<2>>("reference_position");
  for (std::size_t i = 0; i < sim.size(); ++i)
    if (fl.kind[i] == 1) {
      EXPECT_NEAR(double(fl.x[i][0] - x0[i][0]), 0.2 * 0.01, test::real_tol(1e-12, 8));
      EXPECT_EQ(double(fl.v[i][0]), 0.0);
    }
  for (const json& bad : {json{{"type", "spin"}}, json{{"type", "oscillation"}, {"amplitude", {0.1, 0}}},
                          json{{"type", "translation"}, {"velocity", {1, 0}}, {"speed", 2}}}) {
    try {
      Simulation<2> s2(scene::parse_scene_json(tank_scene(bad), "bad.json"));
      ADD_FAILURE() << "accepted " << bad.dump();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("bodies.1.motion"), std::string::npos) << e.what();
    }
  }
}
