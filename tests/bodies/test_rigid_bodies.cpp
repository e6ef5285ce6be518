// Rigid bodies moved by the fluid (bodies/rigid_bodies.hpp): the Newton-Euler step against exact
// solutions, momentum of fluid + bodies kept to round-off, the same bits on 1 and 2 threads and after a
// restart, and bad input refused with exit 2 naming the key.
#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>
#include <numbers>
#include <fstream>
#include <map>
#include <sstream>

#include "bodies/rigid_bodies.hpp"
#include "core/errors.hpp"
#include "scene/scene.hpp"
#include "sim/simulation.hpp"
#include "restart_support.hpp"
#include "test_support.hpp"

using namespace varsph;
using nlohmann::json;

namespace {

// Fluid at rest in a small tank in one corner; the body far from it (gravity only acts on the body).
json free_body_scene(int dim) {
  json j;
  if (dim == 2) {
    j = json::parse(R"({
      "name": "free_body", "setup": "paper", "dimension": 2,
      "domain": {"min": [-0.1, -0.1], "max": [2.0, 2.0]}, "particles": {"spacing": 0.02},
      "kernel": {"type": "wendland_c2", "h_over_dx": 1.414}, "gravity": [0, -9.81],
      "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0], "max": [0.2, 0.1], "initial_pressure": "hydrostatic"},
                 {"kind": "boundary", "shape": "tank", "min": [0, 0], "max": [0.2, 0.2], "layers": 3},
                 {"kind": "rigid", "shape": "box", "min": [1.0, 1.5], "max": [1.2, 1.6], "density": 500}],
      "physics": {"riemann": {}}, "boundary": {"model": "dummy_adami"},
      "integrator": {"type": "symplectic_euler", "dt": 1e-4}, "time": {"end": 1}})");
  } else {
    j = json::parse(R"({
      "name": "free_body", "setup": "paper", "dimension": 3,
      "domain": {"min": [-0.1, -0.1, -0.1], "max": [1.5, 1.5, 1.5]}, "particles": {"spacing": 0.04},
      "kernel": {"type": "wendland_c2", "h_over_dx": 1.414}, "gravity": [0, 0, 0],
      "fluid": {"c0": 10},
      "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0, 0], "max": [0.16, 0.16, 0.12]},
                 {"kind": "boundary", "shape": "tank", "min": [0, 0, 0], "max": [0.16, 0.16, 0.2], "layers": 3},
                 {"kind": "rigid", "shape": "box", "min": [0.8, 0.7, 0.6], "max": [1.2, 0.9, 0.72], "density": 500,
                  "angular_velocity": [3, 1, 2]}],
      "physics": {"riemann": {}}, "boundary": {"model": "dummy_adami"},
      "integrator": {"type": "symplectic_euler", "dt": 1e-4}, "time": {"end": 1}})");
  }
  return j;
}

// A fully periodic box of water at rest with two discs (circles in 2D) on a collision course: an isolated
// system of fluid and bodies exchanging momentum through the wall model and through contact.
json periodic_scene() {
  return json::parse(R"({
    "name": "periodic_bodies", "setup": "paper", "dimension": 2,
    "domain": {"min": [0, 0], "max": [0.4, 0.3], "periodic": [true, true]}, "particles": {"spacing": 0.01},
    "kernel": {"type": "wendland_c2", "h_over_dx": 1.414}, "fluid": {"c0": 15},
    "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0], "max": [0.4, 0.3]},
               {"kind": "rigid", "shape": "sphere", "center": [0.13, 0.15], "radius": 0.04, "density": 3000,
                "velocity": [1.5, 0.1], "angular_velocity": [5]},
               {"kind": "rigid", "shape": "box", "min": [0.2, 0.11], "max": [0.28, 0.19], "density": 1500}],
    "physics": {"riemann": {}}, "boundary": {"model": "dummy_adami"},
    "integrator": {"type": "symplectic_euler", "cfl": 0.2}, "time": {"end": 1}})");
}

Eigen::Vector3d fluid_momentum(const Simulation<2>& sim) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  const auto& f = sim.fields();
  for (std::size_t i = 0; i < sim.size(); ++i)
    if (f.kind[i] == 0) p += Eigen::Vector3d(double(f.mass[i] * f.v[i][0]), double(f.mass[i] * f.v[i][1]), 0);
  return p;
}

}  // namespace

TEST(RigidBodies, FreeFallFollowsTheDiscreteSymplecticEulerSolutionExactly) {
  Simulation<2> sim(scene::parse_scene_json(free_body_scene(2), "free.json"));
  const auto& b = sim.rigid_bodies()->bodies().at(0);
  const double x0 = b.x.y(), dt = 1e-4, g = 9.81;
  EXPECT_NEAR(b.mp.mass, 500 * 0.2 * 0.1, 1e-12);
  for (int n = 1; n <= 300; ++n) sim.advance();
  const double n = 300;
  // v_n = -n g dt, x_n = x_0 - g dt^2 n (n + 1) / 2
  EXPECT_NEAR(b.v.y(), -n * g * dt, 1e-12);
  EXPECT_NEAR(b.x.y(), x0 - g * dt * dt * n * (n + 1) / 2, 1e-12);
  EXPECT_NEAR(b.x.x(), 1.1, 1e-14);
  // its particles are placed rigidly: every one keeps its offset from the centre of mass
  const auto& f = sim.fields();
  const auto& local = sim.store().get<Vec<2>>("rigid_local");
  int seen = 0;
  for (std::size_t i = 0; i < sim.size(); ++i)
    if (f.body[i] == 2) {
      ++seen;
      EXPECT_NEAR(double(f.x[i][1]) - b.x.y(), double(local[i][1]), 1e-12);
      EXPECT_NEAR(double(f.v[i][1]), b.v.y(), 1e-12);
    }
  EXPECT_EQ(seen, 10 * 5);  // the solid box's lattice
}

TEST(RigidBodies, TorqueFreeSpinKeepsAngularMomentumExactlyIn3D) {
  Simulation<3> sim(scene::parse_scene_json(free_body_scene(3), "spin.json"));
  const auto* rb = sim.rigid_bodies();
  const Eigen::Vector3d L0 = rb->angular_momentum();
  const double E0 = rb->kinetic_energy();
  for (int n = 0; n < 2000; ++n) sim.advance();  // 0.2 s: the spin axis precesses (w not along a principal axis)
  const auto& b = rb->bodies().at(0);
  EXPECT_LT((rb->angular_momentum() - L0).norm(), 1e-12 * L0.norm());
  EXPECT_GT((b.w - Eigen::Vector3d(3, 1, 2)).norm(), 0.05);  // it did precess
  EXPECT_LT(std::abs(rb->kinetic_energy() - E0), 2e-3 * E0);  // first-order rotation update
  EXPECT_NEAR(b.q.norm(), 1.0, 1e-14);
}

TEST(RigidBodies, FluidAndBodiesKeepTheirTotalMomentumToRoundOff) {
  Simulation<2> sim(scene::parse_scene_json(periodic_scene(), "periodic.json"));
  auto* rb = sim.rigid_bodies();
  const Eigen::Vector3d P0 = fluid_momentum(sim) + rb->momentum();
  const double scale = rb->bodies()[0].mp.mass * 0.8;
  double max_contact = 0, moved = 0;
  const double x1 = rb->bodies()[1].x.x();
  while (sim.time() < 0.12) {
    sim.advance();
    max_contact = std::max(max_contact, rb->bodies()[0].loads.contact_force.norm());
    const Eigen::Vector3d P = fluid_momentum(sim) + rb->momentum();
    ASSERT_LT((P - P0).norm(), 1e-11 * scale) << "t = " << sim.time();
  }
  moved = rb->bodies()[1].x.x() - x1;
  // momentum went from the disc into the fluid and the block: the exchange was real
  EXPECT_LT(rb->bodies()[0].v.x(), 1.4);
  EXPECT_GT(moved, 1e-3);
  EXPECT_GT(max_contact, 0.0);  // and the two bodies touched
  std::printf("contact force max %.3g N/m, block moved %.3g m, disc vx %.4f\n", max_contact, moved, rb->bodies()[0].v.x());
}

TEST(RigidBodies, TwoThreadsGiveTheBitsOfOne) {
  auto run = [](int threads) {
    omp_set_num_threads(threads);
    Simulation<2> sim(scene::parse_scene_json(periodic_scene(), "periodic.json"));
    for (int n = 0; n < 150; ++n) sim.advance();
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

TEST(RigidBodies, ARestartContinuesBitwise) {
  namespace fs = std::filesystem;
  const fs::path dir = test::scratch_dir("rigid_restart");
  json j = periodic_scene();
  j["time"]["end"] = 0.02;
  j["output"] = {{"every", 0.01}, {"probes_every", 0.002}};
  j["checkpoint"] = {{"every", 0.01}};
  std::ofstream(dir / "scene.json") << j.dump(1);
  const auto t = test::run_full_and_restarted(dir / "scene.json", dir, "0.01", "bodies.csv");
  ASSERT_TRUE(t.error.empty()) << t.error;
  const std::string& full = t.full;
  EXPECT_EQ(full, t.continued);  // stopped at t = 0.01 (its end checkpoint) and continued from it
  EXPECT_GT(std::count(full.begin(), full.end(), '\n'), 20);
}

// Constraints and moorings against closed forms, away from the water (gravity on the body only).
TEST(RigidBodies, PendulumOnAFixedPointSwingsWithItsCompoundPeriod) {
  json j = free_body_scene(2);  // box 0.2 x 0.1 at (1.1, 1.55), pivot 0.25 m above its centre
  j["bodies"][2]["constraint"] = {{"type", "fixed_point"}, {"point", {1.1, 1.8}}};
  j["bodies"][2]["angular_velocity"] = {0.2};  // small swing: theta_max ~ w0 / Omega ~ 0.035 rad
  Simulation<2> sim(scene::parse_scene_json(j, "pendulum.json"));
  const auto& b = sim.rigid_bodies()->bodies().at(0);
  const double M = b.mp.mass, Ic = b.mp.inertia(2, 2), d = 0.25;
  const double T = 2 * std::numbers::pi * std::sqrt((Ic + M * d * d) / (M * 9.81 * d));
  // zero crossings of the angle (downward through 0 from positive) give the period
  double prev = 0, first = -1, last = -1;
  int crossings = 0;
  while (sim.time() < 3.2 * T) {
    sim.advance();
    const double a = 2 * std::atan2(b.q.z(), b.q.w());
    if (prev > 0 && a <= 0) {
      const double tc = sim.time() - sim.dt() * a / (a - prev);
      if (first < 0) first = tc;
      last = tc;
      ++crossings;
    }
    prev = a;
    // the centre of mass stays on its circle about the pivot
    ASSERT_NEAR((b.x - Eigen::Vector3d(1.1, 1.8, 0)).norm(), d, 1e-12);
  }
  ASSERT_GE(crossings, 3);
  const double measured = (last - first) / (crossings - 1);
  EXPECT_NEAR(measured / T, 1.0, 2e-3) << "measured " << measured << " s, compound pendulum " << T << " s";
}

TEST(RigidBodies, BodyOnASpringOscillatesAboutMgOverK) {
  json j = free_body_scene(2);
  const double k = 2000;  // N/m per metre of depth
  j["bodies"][2]["lock_translation"] = {true, false};
  j["bodies"][2]["lock_rotation"] = {true};
  j["bodies"][2]["velocity"] = {0.3, 0};  // locked: stays zero
  j["moorings"] = json::array({{{"body", 2}, {"point", {1.1, 1.6}}, {"anchor", {1.1, 1.9}}, {"stiffness", k}, {"slack", false}}});
  Simulation<2> sim(scene::parse_scene_json(j, "spring.json"));
  const auto& b = sim.rigid_bodies()->bodies().at(0);
  const double M = b.mp.mass, y0 = b.x.y(), T = 2 * std::numbers::pi * std::sqrt(M / k);
  double ymin = 1e9, ymax = -1e9;
  while (sim.time() < 2 * T) {
    sim.advance();
    ymin = std::min(ymin, b.x.y());
    ymax = std::max(ymax, b.x.y());
    ASSERT_EQ(b.x.x(), 1.1);
    ASSERT_EQ(b.v.x(), 0.0);
  }
  // released at the spring's rest length: it swings between y0 and y0 - 2 M g / k about y0 - M g / k
  const double sag = M * 9.81 / k;
  EXPECT_NEAR(0.5 * (ymin + ymax), y0 - sag, 0.01 * sag);
  EXPECT_NEAR(ymax - ymin, 2 * sag, 0.01 * sag);
  // the line's length as evaluated for the last step's load: one step (|v| dt < 1e-4 m) behind the state
  EXPECT_NEAR(sim.rigid_bodies()->moorings()[0].length, 0.3 + (y0 - b.x.y()), 1e-4);
}

TEST(RigidBodies, HingeIn3DTurnsAboutItsAxisOnly) {
  json j = free_body_scene(3);  // box 0.4 x 0.2 x 0.12 centred at (1, 0.8, 0.66), spinning (3, 1, 2) rad/s
  j["gravity"] = {0, 0, -9.81};
  j["bodies"][2]["constraint"] = {{"type", "hinge"}, {"point", {1.0, 0.8, 0.9}}, {"axis", {1, 0, 0}}};
  Simulation<3> sim(scene::parse_scene_json(j, "hinge.json"));
  const auto& b = sim.rigid_bodies()->bodies().at(0);
  for (int n = 0; n < 1500; ++n) {
    sim.advance();
    ASSERT_NEAR(b.w.y(), 0.0, 1e-14);
    ASSERT_NEAR(b.w.z(), 0.0, 1e-14);
    ASSERT_NEAR(b.x.x(), 1.0, 1e-12);  // the centre of mass turns in the plane x = 1 about the axis
    ASSERT_NEAR(std::hypot(b.x.y() - 0.8, b.x.z() - 0.9), 0.24, 1e-12);
  }
  EXPECT_GT(std::abs(b.w.x()), 0.5);  // swinging under gravity about x
}

// The box of pipelines/bodies/floating_box_2d.json at its Archimedes draft, coarse, through every wall model:
// the fluid carries its weight (the mean vertical fluid force over 0.1-0.25 s within 10 % of M g).
TEST(RigidBodies, EveryWallModelFloatsTheBox) {
  const std::vector<std::vector<std::string>> models = {
      {"boundary.model=\"dummy_adami\""},
      {"boundary.model=\"dynamic\"", "physics.riemann=null", "physics.artificial_viscosity={\"alpha\": 0.1}"},
      {"boundary.model=\"mdbc\""},
      {"boundary.model=\"repulsive\"", "physics.riemann=null", "physics.artificial_viscosity={\"alpha\": 0.1}"}};
  for (const auto& m : models) {
    std::vector<std::string> o = {"particles.spacing=0.02", "time.end=0.25", "bodies.2.min=[0.5, 0.35]",
                                  "bodies.2.max=[0.7, 0.45]"};
    o.insert(o.end(), m.begin(), m.end());
    Simulation<2> sim(scene::parse_scene(test::source_dir() / "pipelines" / "bodies" / "floating_box_2d.json", o));
    const auto& b = sim.rigid_bodies()->bodies().at(0);
    double sum = 0, w = 0;
    while (sim.time() < 0.25) {
      sim.advance();
      if (sim.time() > 0.1) {
        sum += b.loads.fluid_force.y() * sim.dt();
        w += sim.dt();
      }
    }
    const double weight = b.mp.mass * 9.81;
    std::printf("%s: mean fluid force %.2f N/m, weight %.2f N/m, centre %.4f m\n", m[0].c_str(), sum / w, weight, b.x.y());
    EXPECT_NEAR(sum / w / weight, 1.0, 0.1) << m[0];
  }
}

// Blocks carried by a dam break (pipelines/bodies/dam_break_blocks_2d.json, coarse): at every check no fluid
// particle is trapped inside a block, and no block particle comes closer than half a spacing to a particle of another
// body (a wall or the other block): contact holds at the flow's 2-3 m/s.
TEST(RigidBodies, BlocksInADamBreakNeitherTrapWaterNorPassThroughWalls) {
  Simulation<2> sim(scene::parse_scene(test::source_dir() / "pipelines" / "bodies" / "dam_break_blocks_2d.json",
                                       {"particles.spacing=0.02", "time.end=1.0"}));
  const auto* rb = sim.rigid_bodies();
  const auto& f = sim.fields();
  const double dx = 0.02;
  const double half[2][2] = {{0.05, 0.05}, {0.06, 0.04}};
  double closest = 1e9, deepest = -1e9, vmax = 0;
  long checks = 0;
  while (sim.time() < 1.0) {
    sim.advance();
    for (const auto& b : rb->bodies()) vmax = std::max(vmax, b.v.norm());
    if (sim.step() % 25 != 0) continue;
    ++checks;
    for (std::size_t k = 0; k < 2; ++k) {
      const auto& b = rb->bodies()[k];
      const Eigen::Matrix3d Rt = b.q.toRotationMatrix().transpose();
      for (std::size_t i = 0; i < sim.size(); ++i) {
        const Eigen::Vector3d r = Rt * (Eigen::Vector3d(double(f.x[i][0]), double(f.x[i][1]), 0) - b.x);
        // how far inside the block's surface (positive: inside)
        const double inside = std::min(half[k][0] - std::abs(r.x()), half[k][1] - std::abs(r.y()));
        if (f.kind[i] == 0) deepest = std::max(deepest, inside);
        else if (f.body[i] != b.scene_index && inside > -dx) {
          // another body's particle near this block: its distance to the block's particles
          for (std::size_t j = 0; j < sim.size(); ++j)
            if (f.body[j] == b.scene_index)
              closest = std::min(closest, double((f.x[i] - f.x[j]).norm()));
        }
      }
    }
  }
  std::printf("dam-break blocks: %ld checks, top speed %.2f m/s, deepest fluid %.3f dx inside a block, "
              "closest approach of two bodies %.3f dx\n", checks, vmax, deepest / dx, closest / dx);
  EXPECT_GT(vmax, 1.5);               // they were carried
  // no fluid particle trapped among a block's particles: none deeper than its first layer (0.5 dx inside
  // the surface) by half a spacing (measured: 0.55 dx at the corners of the fast blocks, dx = 0.02)
  EXPECT_LT(deepest, 1.0 * dx);
  EXPECT_GT(closest, 0.5 * dx);       // no interpenetration
}

TEST(RigidBodies, BadInputIsRefusedNamingTheKey) {
  auto refused = [](json j, const std::string& key) {
    try {
      Simulation<2> sim(scene::parse_scene_json(j, "bad.json"));
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "accepted, expected an error naming " << key;
  };
  json j = free_body_scene(2);
  j["bodies"][2].erase("density");
  j["bodies"][2]["mass"] = 0;
  refused(j, "bodies.2.mass");
  j = free_body_scene(2);
  j["bodies"][2]["mass"] = 3;
  refused(j, "bodies.2.density");  // both given
  j = free_body_scene(2);
  j["integrator"]["type"] = "rk4";
  refused(j, "integrator.type");
  j = free_body_scene(2);
  j["integrator"]["type"] = "variational";  // with dummy walls: the midpoints do not extrapolate them
  refused(j, "boundary.model");
  j = free_body_scene(2);
  j["bodies"][2]["constraint"] = {{"type", "hinge"}};
  refused(j, "bodies.2.constraint.point");
  j = free_body_scene(2);
  j["moorings"] = json::array({{{"body", 1}, {"point", {1.1, 1.5}}, {"anchor", {1.1, 0.5}}, {"stiffness", 100}}});
  refused(j, "moorings.0.body");
  j = free_body_scene(2);
  j["moorings"] = json::array({{{"body", 2}, {"point", {1.1, 1.5}}, {"anchor", {1.1, 1.55}}, {"stiffness", 100}}});
  refused(j, "moorings.0.anchor");  // inside the body
  j = free_body_scene(2);
  j["bodies"][2]["min"] = {0.1, 0.15};  // inside the tank's wall and over the water
  j["bodies"][2]["max"] = {0.3, 0.25};
  refused(j, "bodies.2");
  j = free_body_scene(2);
  j["bodies"][2]["shape"] = "tank";
  refused(j, "bodies.2.shape");
  // 3D: an inertia tensor that is not positive definite, a hinge axis of zero length
  json k = free_body_scene(3);
  k["bodies"][2].erase("density");
  k["bodies"][2]["mass"] = 2;
  k["bodies"][2]["inertia"] = {1, 1, -1, 0, 0, 0};
  try {
    Simulation<3> sim(scene::parse_scene_json(k, "bad.json"));
    ADD_FAILURE() << "accepted a negative inertia";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies.2.inertia"), std::string::npos) << e.what();
  }
  k = free_body_scene(3);
  k["bodies"][2]["constraint"] = {{"type", "hinge"}, {"point", {1, 0.8, 0.6}}, {"axis", {0, 0, 0}}};
  try {
    Simulation<3> sim(scene::parse_scene_json(k, "bad.json"));
    ADD_FAILURE() << "accepted a zero axis";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies.2.constraint.axis"), std::string::npos) << e.what();
  }
}

TEST(RigidBodies, ABodyThatLeavesTheDomainIsReportedNotACrash) {
  json j = free_body_scene(2);
  j["bodies"][2]["velocity"] = {0, 60};  // up and out within 0.01 s
  Simulation<2> sim(scene::parse_scene_json(j, "leave.json"));
  try {
    for (int n = 0; n < 200; ++n) sim.advance();
    ADD_FAILURE() << "the body left the domain unnoticed";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies.2 left the domain"), std::string::npos) << e.what();
  }
}
