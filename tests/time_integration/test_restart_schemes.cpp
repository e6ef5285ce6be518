// The explicit schemes keep no state across steps beyond registered, checkpointed fields: a run restored
// from a mid-run snapshot (as a restart does: fields, clock, dt, integrator state, then sort_and_bin)
// continues bitwise identically, with CFL-adaptive dt and the Shepard re-initialisation on.
#include <gtest/gtest.h>

#include <cstring>

#include "scene/json_reader.hpp"
#include "scene/scene.hpp"
#include "sim/restart.hpp"
#include "sim/simulation.hpp"
#include "test_support.hpp"

using namespace varsph;

TEST(RestartSchemes, SnapshotRestartIsBitwiseIdentical) {
  const auto file = test::source_dir() / "pipelines" / "dam_break_2d_paper.json";
  for (const char* type : {"symplectic_euler", "predictor_corrector", "rk4", "verlet_dsph"}) {
    nlohmann::json j = scene::read_json_file(file);
    j["integrator"] = {{"type", type}, {"cfl", 0.2}};
    j["physics"]["shepard_reinit"] = {{"every", 7}};
    const auto sc = scene::parse_scene_json(j, file);
    Simulation<2> a(sc);
    StateSnapshot<2> snap;
    for (int k = 0; k < 40; ++k) {
      if (k == 17) snap.capture(a, nlohmann::json::object());
      a.advance();
    }
    Simulation<2> b(sc);
    snap.restore(b);
    ASSERT_EQ(b.step(), 17);  // 23 steps from the snapshot, not 40 from the start
    b.sort_and_bin();
    while (b.step() < a.step()) b.advance();
    EXPECT_EQ(a.time(), b.time()) << type;
    EXPECT_EQ(a.dt(), b.dt()) << type;
    const auto& fa = a.fields();
    const auto& fb = b.fields();
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(0, std::memcmp(fa.x.data.data(), fb.x.data.data(), a.size() * sizeof(Vec<2>))) << type;
    EXPECT_EQ(0, std::memcmp(fa.v.data.data(), fb.v.data.data(), a.size() * sizeof(Vec<2>))) << type;
    EXPECT_EQ(0, std::memcmp(fa.rho.data.data(), fb.rho.data.data(), a.size() * sizeof(Real))) << type;
  }
}

// The runner keeps one snapshot every 100 steps and, on a blow-up, restores it and replays the steps up to
// the last good one (StateSnapshot::replay_to): in the same simulation that has meanwhile run past it, the
// replayed state must be bitwise the one the run had at that step.
TEST(RestartSchemes, ReplayFromAnEarlierSnapshotReproducesTheStepBitwise) {
  const auto file = test::source_dir() / "pipelines" / "dam_break_2d_paper.json";
  // verlet_dsph (the scheme with the most cross-step state) and variational (fixed point, extrapolated guess).
  for (const char* type : {"verlet_dsph", "variational"}) {
    nlohmann::json j = scene::read_json_file(file);
    j["integrator"] = std::string(type) == "variational" ? nlohmann::json{{"type", type}, {"dt", 1e-4}, {"alpha", 0.5}}
                                                         : nlohmann::json{{"type", type}, {"cfl", 0.2}};
    const auto sc = scene::parse_scene_json(j, file);
    Simulation<2> a(sc);
    StateSnapshot<2> snap;
    for (int k = 0; k < 20; ++k) {
      if (k == 7) snap.capture(a, nlohmann::json::object());
      a.advance();
    }
    const std::vector<Vec<2>> x = a.fields().x.data, v = a.fields().v.data;
    const std::vector<Real> rho = a.fields().rho.data;
    const double t = a.time(), dt = a.dt();
    for (int k = 0; k < 3; ++k) a.advance();  // the steps after the last good one
    EXPECT_EQ(snap.replay_to(a, 20), 13) << type;
    ASSERT_EQ(a.step(), 20);
    EXPECT_EQ(a.time(), t) << type;
    EXPECT_EQ(a.dt(), dt) << type;
    EXPECT_EQ(0, std::memcmp(x.data(), a.fields().x.data.data(), x.size() * sizeof(Vec<2>))) << type;
    EXPECT_EQ(0, std::memcmp(v.data(), a.fields().v.data.data(), v.size() * sizeof(Vec<2>))) << type;
    EXPECT_EQ(0, std::memcmp(rho.data(), a.fields().rho.data.data(), rho.size() * sizeof(Real))) << type;
  }
}
