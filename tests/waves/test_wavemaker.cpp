// Wavemakers and the damping zone in the solver: the paddle's particles follow the wave-theory signal (piston:
// translation, flap: rotation about the hinge) with its velocity and acceleration; bad input is refused before
// the run (exit 2) naming the key and the limit; the damping zone relaxes velocities by its documented profile
// only where it lies; a restarted wave flume continues bitwise.
#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>

#include "core/errors.hpp"
#include "physics/damping_zone.hpp"
#include "real_tolerance.hpp"
#include "scene/scene.hpp"
#include "sim/simulation.hpp"
#include "restart_support.hpp"
#include "test_support.hpp"
#include "waves/paddle_signal.hpp"
#include "waves/wave_theory.hpp"

using namespace varsph;
using nlohmann::json;

namespace {

constexpr double kDepth = 0.1, kDx = 0.01;

// A small 2D flume: water 1 m x 0.1 m, a bed under the paddle's whole stroke, a wall at the far end, the
// paddle (body 3) a block of three layers left of the water. The engineering set-up (docs/validation.md).
json flume(const json& motion) {
  json j = json::parse(R"({
    "name": "flume", "setup": "paper", "dimension": 2,
    "domain": {"min": [-0.3, -0.1], "max": [1.2, 0.4]}, "particles": {"spacing": 0.01},
    "kernel": {"type": "wendland_c2", "h_over_dx": 1.414}, "gravity": [0, -9.81],
    "physics": {"riemann": {}}, "boundary": {"model": "dummy_adami"},
    "integrator": {"type": "symplectic_euler", "cfl": 0.2}, "time": {"end": 1},
    "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0], "max": [1.0, 0.1], "initial_pressure": "hydrostatic"},
               {"kind": "boundary", "shape": "box", "min": [-0.25, -0.03], "max": [1.03, 0], "layers": 3},
               {"kind": "boundary", "shape": "box", "min": [1.0, 0], "max": [1.03, 0.2], "layers": 3},
               {"kind": "boundary", "shape": "box", "min": [-0.03, 0], "max": [0, 0.16], "layers": 3}]})");
  j["bodies"][3]["motion"] = motion;
  return j;
}

json regular(const std::string& type, double H, double T) {
  json m = {{"type", type}, {"waves", "regular"}, {"height", H}, {"period", T}, {"ramp", 0.1}};
  if (type == "flap") m["hinge"] = {-0.015, 0.0};
  return m;
}

}  // namespace

TEST(Wavemaker, PistonFollowsTheBieselStrokeWithItsVelocityAndAcceleration) {
  const double H = 0.01, T = 1.0;
  Simulation<2> sim(scene::parse_scene_json(flume(regular("piston", H, T)), "piston.json"));
  // the signal the scene means: stroke S = H / (H/S), ramped over 2 T
  const waves::PaddleGeometry geo{.flap = false, .depth = kDepth, .g = 9.81};
  auto sig = waves::PaddleSignal::sines(waves::regular_waves(geo, H, T, 0, 1));
  sig.set_ramp(0.1);
  const double k = waves::wave_number(2 * std::numbers::pi / T, kDepth, 9.81);
  EXPECT_NEAR(2 * sig.components()[0].amplitude, H / waves::piston_transfer(k * kDepth), 1e-15);
  for (int n = 0; n < 300; ++n) sim.advance();
  const double t = sim.time();
  const auto X = sig.at(t);
  EXPECT_GT(std::abs(X.q), 1e-5);  // moving
  const auto& f = sim.fields();
  const auto& x0 = sim.store().get<Vec<2>>("reference_position");
  const auto& acc = sim.store().get<Vec<2>>("wall_acceleration");
  int paddle = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.body[i] != 3) continue;
    ++paddle;
    EXPECT_NEAR(double(f.x[i][0]), double(x0[i][0]) + X.q, test::real_tol(1e-14, 8));
    EXPECT_EQ(f.x[i][1], x0[i][1]);
    EXPECT_NEAR(double(f.v[i][0]), X.dq, test::real_tol(1e-14, 8));
    EXPECT_EQ(double(f.v[i][1]), 0.0);
    EXPECT_NEAR(double(acc[i][0]), X.ddq, test::real_tol(1e-12, 8));
  }
  EXPECT_EQ(paddle, 3 * 16);
  // no water passed the paddle
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.kind[i] == 0) {
      EXPECT_GT(double(f.x[i][0]), X.q) << "fluid particle behind the paddle's face";
    }
  }
}

TEST(Wavemaker, FlapTurnsAboutItsHingeSoThatTheStillWaterLevelMovesByX) {
  const double H = 0.01, T = 1.0;
  json m = regular("flap", H, T);
  Simulation<2> sim(scene::parse_scene_json(flume(m), "flap.json"));
  // hinge on the bed (l = 0): arm = h
  const waves::PaddleGeometry geo{.flap = true, .depth = kDepth, .hinge_height = 0, .g = 9.81};
  auto sig = waves::PaddleSignal::sines(waves::regular_waves(geo, H, T, 0, 1));
  sig.set_ramp(0.1);
  for (int n = 0; n < 300; ++n) sim.advance();
  const double t = sim.time(), X = sig.at(t).q, theta = std::atan(X / kDepth);
  const auto& f = sim.fields();
  const auto& x0 = sim.store().get<Vec<2>>("reference_position");
  const Vec<2> c(Real(-0.015), Real(0));
  int checked = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.body[i] != 3) continue;
    const Vec<2> r0 = x0[i] - c, r = f.x[i] - c;
    EXPECT_NEAR(double(r.norm()), double(r0.norm()), test::real_tol(1e-14, 8));
    // clockwise by theta: the top moves towards +x
    EXPECT_NEAR(double(r[0]), std::cos(theta) * double(r0[0]) + std::sin(theta) * double(r0[1]), test::real_tol(1e-14, 8));
    // v = omega x r with omega = -theta' (about z)
    const double dtheta = kDepth * sig.at(t).dq / (kDepth * kDepth + X * X);
    EXPECT_NEAR(double(f.v[i][0]), dtheta * double(r[1]), test::real_tol(1e-13, 16));
    EXPECT_NEAR(double(f.v[i][1]), -dtheta * double(r[0]), test::real_tol(1e-13, 16));
    ++checked;
  }
  EXPECT_EQ(checked, 48);
  // the point of the paddle's centre line at the still-water level moves by X horizontally (tan theta = X / h)
  EXPECT_NEAR(kDepth * std::tan(theta), X, 1e-15);
}

TEST(Wavemaker, BadInputIsRefusedNamingTheKeyAndTheLimit) {
  const std::string dir = test::scratch_dir("wavemaker_bad").string();
  struct Case {
    json motion;
    std::string key, limit;
  };
  std::ofstream(dir + "/nan.csv") << "time,displacement\n0,0\n0.1,nan\n";
  std::ofstream(dir + "/back.csv") << "0,0\n0.1,0.001\n0.05,0.002\n";
  json deep = regular("piston", 0.09, 1.0);              // H/h = 0.9
  json steep = regular("piston", 0.05, 0.3);             // H/L ~ 0.36 at kh ~ 4.5
  json far = regular("piston", 0.07, 6.0);               // shallow: the stroke ~ 0.7 m leaves the domain
  json depth = regular("piston", 0.01, 1.0);
  depth["depth"] = 0.2;
  json band = {{"type", "piston"}, {"waves", "irregular"}, {"hs", 0.01}, {"tp", 1.0}, {"f_min", 5.0}, {"f_max", 6.0}};
  json order = regular("flap", 0.01, 1.0);
  order["order"] = 2;
  json hinge = regular("flap", 0.01, 1.0);
  hinge["hinge"] = {-0.015, 0.12};
  json nan = {{"type", "piston"}, {"waves", "file"}, {"file", "nan.csv"}};
  json back = {{"type", "piston"}, {"waves", "file"}, {"file", "back.csv"}};
  json typo = regular("piston", 0.01, 1.0);
  typo["heigth"] = 0.01;
  const Case cases[] = {{deep, "motion.height", "0.78"},
                        {steep, "motion.height", "Miche"},
                        {far, "bodies.3.motion", "leaves the domain"},
                        {depth, "motion.depth", "does not match"},
                        {band, "motion.f_min", "of the spectrum's energy"},
                        {order, "motion.order", "piston"},
                        {hinge, "motion.hinge", "below the"},
                        {nan, "motion.file", "not a finite number"},
                        {back, "motion.file", "does not increase"},
                        {typo, "bodies.3.motion", "did you mean 'height'"}};
  for (const auto& c : cases) {
    json j = flume(c.motion);
    std::string what;
    try {
      Simulation<2> sim(scene::parse_scene_json(j, dir + "/scene.json"));
      what = "accepted";
    } catch (const InputError& e) {
      what = e.what();
    }
    EXPECT_NE(what.find(c.key), std::string::npos) << c.motion.dump() << ": " << what;
    EXPECT_NE(what.find(c.limit), std::string::npos) << c.motion.dump() << ": " << what;
  }
}

TEST(DampingZone, RelaxesVelocityByTheQuadraticProfileOnlyInsideTheZone) {
  physics::DampingZone<2> z;
  z.from = Vec<2>(Real(2), Real(0));
  z.normal = Vec<2>(Real(1), Real(0));
  z.length = 1;
  z.beta = 10;
  const Real dt = Real(1e-3);
  EXPECT_EQ(z.factor(Vec<2>(Real(1.5), Real(0.3)), dt), Real(1));
  EXPECT_EQ(z.factor(Vec<2>(Real(2.0), Real(0.3)), dt), Real(1));
  EXPECT_NEAR(double(z.factor(Vec<2>(Real(2.5), Real(0.3)), dt)), 1 - 1e-3 * 10 * 0.25, test::real_tol(1e-15, 4));
  EXPECT_NEAR(double(z.factor(Vec<2>(Real(3.5), Real(0.3)), dt)), 1 - 1e-3 * 10, test::real_tol(1e-15, 4));
  EXPECT_EQ(z.factor(Vec<2>(Real(3.5), Real(0.3)), Real(1)), Real(0));  // never reverses a velocity
  z.quadratic = false;
  EXPECT_NEAR(double(z.factor(Vec<2>(Real(2.5), Real(0.3)), dt)), 1 - 1e-3 * 10 * 0.5, test::real_tol(1e-15, 4));
}

TEST(DampingZone, InTheSolverDampsTheFluidBeyondFromAndNothingElse) {
  // a periodic stream without gravity: uniform, so the pair forces vanish and one step multiplies each
  // fluid velocity by the zone's factor at its new position
  json j = json::parse(R"({
    "name": "stream", "setup": "paper", "dimension": 2,
    "domain": {"min": [0, 0], "max": [0.4, 0.2], "periodic": [true, true]}, "particles": {"spacing": 0.01},
    "kernel": {"type": "wendland_c2", "h_over_dx": 1.414}, "fluid": {"c0": 10},
    "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0], "max": [0.4, 0.2], "velocity": [0.5, 0]}],
    "physics": {"riemann": {}}, "integrator": {"type": "symplectic_euler", "dt": 1e-4}, "time": {"end": 1},
    "physics": {"riemann": {}, "damping_zone": {"from": [0.2, 0], "to": [0.3, 0], "beta": 20}}})");
  Simulation<2> sim(scene::parse_scene_json(j, "zone.json"));
  sim.advance();
  const auto& f = sim.fields();
  int inside = 0, beyond = 0, before = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    const double x = double(f.x[i][0]), s = std::clamp((x - 0.2) / 0.1, 0.0, 1.0);
    EXPECT_NEAR(double(f.v[i][0]), 0.5 * (1 - 1e-4 * 20 * s * s), test::real_tol(1e-12, 64)) << x;
    EXPECT_NEAR(double(f.v[i][1]), 0.0, test::real_tol(1e-12, 64));
    (s <= 0 ? before : s >= 1 ? beyond : inside) += 1;
  }
  EXPECT_GT(inside, 50);
  EXPECT_GT(beyond, 50);
  EXPECT_GT(before, 50);
  // a zone whose ends coincide is refused naming the key
  j["physics"]["damping_zone"]["to"] = {0.2, 0};
  try {
    scene::parse_scene_json(j, "zone.json");
    ADD_FAILURE() << "accepted a zone of length 0";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("physics.damping_zone.to"), std::string::npos) << e.what();
  }
}

TEST(Wavemaker, TwoThreadsGiveTheBitsOfOne) {
  auto run = [](int threads) {
    omp_set_num_threads(threads);
    json j = flume(regular("flap", 0.01, 1.0));
    j["bodies"][3]["motion"]["ramp"] = 0;  // the paddle moves from the first step
    j["physics"]["damping_zone"] = {{"from", {0.7, 0}}, {"to", {1.0, 0}}};
    Simulation<2> sim(scene::parse_scene_json(j, "flap.json"));
    for (int n = 0; n < 30; ++n) sim.advance();
    omp_set_num_threads(1);
    std::map<std::int64_t, std::array<double, 4>> by_id;
    const auto& f = sim.fields();
    for (std::size_t i = 0; i < sim.size(); ++i)
      by_id[f.id[i]] = {double(f.x[i][0]), double(f.x[i][1]), double(f.v[i][0]), double(f.v[i][1])};
    return by_id;
  };
  EXPECT_TRUE(run(1) == run(2));
}

TEST(Wavemaker, ARestartContinuesBitwise) {
  namespace fs = std::filesystem;
  const fs::path dir = test::scratch_dir("wavemaker_restart");
  json j = flume(regular("piston", 0.01, 1.0));
  j["physics"]["damping_zone"] = {{"from", {0.7, 0}}, {"to", {1.0, 0}}};
  j["time"]["end"] = 0.04;
  j["output"] = {{"every", 0.02}, {"probes_every", 0.002}};
  j["checkpoint"] = {{"every", 0.02}};
  j["probes"] = {{{"type", "water_height"}, {"name", "g1"}, {"from", {0.3, 0.0}}},
                 {{"type", "force"}, {"name", "paddle"}, {"body", 3}}};
  std::ofstream(dir / "scene.json") << j.dump(1);
  const auto t = test::run_full_and_restarted(dir / "scene.json", dir, "0.02", "probes.csv");
  ASSERT_TRUE(t.error.empty()) << t.error;
  const std::string& full = t.full;
  EXPECT_EQ(full, t.continued);
  EXPECT_GT(std::count(full.begin(), full.end(), '\n'), 15);
}

TEST(Wavemaker, FlapIn3DTurnsAboutTheYAxisTopTowardsPlusX) {
  // a basin section 0.16 m wide, periodic across (y); vertical z; the flap hinged on the bed at x = -0.015
  json j = json::parse(R"({
    "name": "basin", "setup": "paper", "dimension": 3,
    "domain": {"min": [-0.2, 0, -0.1], "max": [0.7, 0.16, 0.3], "periodic": [false, true, false]},
    "particles": {"spacing": 0.02},
    "kernel": {"type": "wendland_c2", "h_over_dx": 1.414}, "gravity": [0, 0, -9.81],
    "physics": {"riemann": {}}, "boundary": {"model": "dummy_adami"},
    "integrator": {"type": "symplectic_euler", "cfl": 0.2}, "time": {"end": 1},
    "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0, 0], "max": [0.6, 0.16, 0.1], "initial_pressure": "hydrostatic"},
               {"kind": "boundary", "shape": "box", "min": [-0.15, 0, -0.06], "max": [0.66, 0.16, 0], "layers": 3},
               {"kind": "boundary", "shape": "box", "min": [0.6, 0, 0], "max": [0.66, 0.16, 0.2], "layers": 3},
               {"kind": "boundary", "shape": "box", "min": [-0.16, 0, 0], "max": [0, 0.16, 0.16], "layers": 3,
                "motion": {"type": "flap", "hinge": [-0.03, 0.08, 0], "height": 0.01, "period": 1.0, "ramp": 0}}]})");
  Simulation<3> sim(scene::parse_scene_json(j, "basin.json"));
  for (int n = 0; n < 40; ++n) sim.advance();
  const waves::PaddleGeometry geo{.flap = true, .depth = 0.1, .hinge_height = 0, .g = 9.81};
  const auto sig = waves::PaddleSignal::sines(waves::regular_waves(geo, 0.01, 1.0, 0, 1));
  const double t = sim.time(), X = sig.at(t).q, theta = std::atan(X / 0.1);
  ASSERT_GT(X, 1e-4);  // the top has moved towards +x
  const auto& f = sim.fields();
  const auto& x0 = sim.store().get<Vec<3>>("reference_position");
  int checked = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.body[i] != 3) continue;
    const double rx = double(x0[i][0]) + 0.03, rz = double(x0[i][2]);
    EXPECT_NEAR(double(f.x[i][0]) + 0.03, std::cos(theta) * rx + std::sin(theta) * rz, test::real_tol(1e-14, 8));
    EXPECT_NEAR(double(f.x[i][2]), -std::sin(theta) * rx + std::cos(theta) * rz, test::real_tol(1e-14, 8));
    EXPECT_NEAR(double(f.x[i][1]), double(x0[i][1]), test::real_tol(1e-15, 4));  // c + (x0 - c) rounds
    ++checked;
  }
  EXPECT_GT(checked, 50);
}
