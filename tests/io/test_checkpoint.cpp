// Checkpoint file: round trip, validation of damaged or foreign files, restore, last-good snapshot.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <fstream>

#include "core/errors.hpp"
#include "io/checkpoint.hpp"
#include "results_scenes.hpp"
#include "scene/scene.hpp"
#include "sim/restart.hpp"
#include "sim/simulation.hpp"
#include "test_support.hpp"

using namespace varsph;
namespace fs = std::filesystem;

namespace {

scene::Scene tiny(const std::vector<std::string>& overrides = {}) {
  return scene::parse_scene_json(test::tiny_dam_break(), "tiny.json", overrides);
}

bool same_arrays(const ParticleStore& a, const ParticleStore& b) {
  for (const auto& f : a.fields()) {
    if (!f->flags().checkpointed) continue;
    const FieldBase* g = b.find(f->name());
    if (!g || g->size() != f->size()) return false;
    if (std::memcmp(f->raw(), g->raw(), f->bytes_per_particle() * f->size()) != 0) return false;
  }
  return true;
}

}  // namespace

TEST(Checkpoint, RoundTripHoldsEveryCheckpointedFieldBitwise) {
  const auto dir = test::scratch_dir("ckpt_roundtrip");
  Simulation<2> sim(tiny());
  for (int k = 0; k < 20; ++k) sim.advance();
  const auto path = dir / io::checkpoint_file_name(sim.step());
  io::write_checkpoint(path, checkpoint_header(sim, {{"frame_index", 3}}), sim.store());
  EXPECT_FALSE(fs::exists(path.string() + ".tmp"));
  const io::Checkpoint c = io::read_checkpoint(path);
  EXPECT_EQ(c.header.step, 20);
  EXPECT_EQ(c.header.time, sim.time());
  EXPECT_EQ(c.header.dt, sim.dt());
  EXPECT_EQ(c.header.dimension, 2);
  EXPECT_EQ(c.header.format_version, io::kCheckpointFormatVersion);
  EXPECT_EQ(c.header.program_version, VARSPH_VERSION);
  EXPECT_EQ(c.header.integrator, "verlet");
  EXPECT_EQ(c.header.scene, sim.scene().resolved);
  EXPECT_EQ(c.header.runner_state.at("frame_index"), 3);
  std::vector<std::string> expected;
  for (const auto& f : sim.store().fields())
    if (f->flags().checkpointed) expected.push_back(f->name());
  std::vector<std::string> got;
  for (const auto& a : c.arrays) got.push_back(a.name);
  EXPECT_EQ(got, expected);  // registry order
  for (const auto& a : c.arrays) {
    const FieldBase* f = sim.store().find(a.name);
    ASSERT_EQ(a.bytes.size(), f->bytes_per_particle() * sim.size());
    EXPECT_EQ(std::memcmp(a.bytes.data(), f->raw(), a.bytes.size()), 0) << a.name;
  }
  // restoring into a fresh simulation and stepping on equals stepping the original
  Simulation<2> other(tiny());
  restore_from_checkpoint(other, c, path.string());
  EXPECT_TRUE(same_arrays(sim.store(), other.store()));
  for (int k = 0; k < 30; ++k) {
    sim.advance();
    other.advance();
  }
  EXPECT_TRUE(same_arrays(sim.store(), other.store()));
  EXPECT_EQ(sim.time(), other.time());
}

TEST(Checkpoint, TruncatedCorruptedAndNewerFilesAreInputErrors) {
  const auto dir = test::scratch_dir("ckpt_damaged");
  Simulation<2> sim(tiny());
  sim.advance();
  const auto good = dir / "good.h5";
  io::write_checkpoint(good, checkpoint_header(sim, {}), sim.store());
  const auto size = fs::file_size(good);

  const auto truncated = dir / "truncated.h5";
  fs::copy_file(good, truncated);
  fs::resize_file(truncated, size / 2);
  EXPECT_THROW(io::read_checkpoint(truncated), InputError);

  // flip bytes in the middle (particle data or metadata): the Fletcher-32 / metadata checksums catch it
  for (double where : {0.3, 0.5, 0.7, 0.9}) {
    const auto corrupted = dir / "corrupted.h5";
    fs::remove(corrupted);
    fs::copy_file(good, corrupted);
    std::fstream f(corrupted, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(std::streamoff(double(size) * where));
    const char junk[16] = {'\x5a', '\x5a', '\x5a', '\x5a', '\x5a', '\x5a', '\x5a', '\x5a',
                           '\x5a', '\x5a', '\x5a', '\x5a', '\x5a', '\x5a', '\x5a', '\x5a'};
    f.write(junk, sizeof junk);
    f.close();
    // either the damage is detected, or it hit unused space and the content is intact: never wrong data
    try {
      const io::Checkpoint c = io::read_checkpoint(corrupted);
      const io::Checkpoint ok = io::read_checkpoint(good);
      ASSERT_EQ(c.arrays.size(), ok.arrays.size());
      for (std::size_t k = 0; k < c.arrays.size(); ++k)
        EXPECT_TRUE(c.arrays[k].bytes == ok.arrays[k].bytes) << "undetected corruption at " << where;
      EXPECT_EQ(c.header.scene, ok.header.scene);
    } catch (const InputError&) {
    }
  }

  const auto text = dir / "text.h5";
  std::ofstream(text) << "not hdf5";
  EXPECT_THROW(io::read_checkpoint(text), InputError);
  EXPECT_THROW(io::read_checkpoint(dir / "missing.h5"), InputError);

  auto h = checkpoint_header(sim, {});
  h.format_version = io::kCheckpointFormatVersion + 1;
  const auto newer = dir / "newer.h5";
  io::write_checkpoint(newer, h, sim.store());
  try {
    io::read_checkpoint(newer);
    FAIL() << "newer format accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("newer"), std::string::npos) << e.what();
  }
}

TEST(Checkpoint, MismatchedSceneIsRefusedAndLeavesTheSimulationUntouched) {
  const auto dir = test::scratch_dir("ckpt_mismatch");
  Simulation<2> sim(tiny());
  sim.advance();
  const auto path = dir / "c.h5";
  io::write_checkpoint(path, checkpoint_header(sim, {}), sim.store());
  io::Checkpoint c = io::read_checkpoint(path);

  Simulation<2> other(tiny({"particles.spacing=0.025"}));
  try {
    restore_from_checkpoint(other, c, path.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'particles.spacing'"), std::string::npos) << e.what();
  }
  EXPECT_EQ(other.step(), 0);

  // output, checkpoint, probes, log and time.end may change
  Simulation<2> relaxed(tiny({"time.end=1", "output.every=0.01", "checkpoint.every_steps=7", "probes=[]"}));
  EXPECT_NO_THROW(restore_from_checkpoint(relaxed, c, path.string()));
  EXPECT_EQ(relaxed.step(), 1);

  io::Checkpoint wrong_count = c;
  wrong_count.header.particles += 1;
  Simulation<2> fresh(tiny());
  EXPECT_THROW(restore_from_checkpoint(fresh, wrong_count, path.string()), InputError);
  io::Checkpoint wrong_dim = c;
  wrong_dim.header.dimension = 3;
  EXPECT_THROW(restore_from_checkpoint(fresh, wrong_dim, path.string()), InputError);
}

TEST(Checkpoint, FirstPhysicsDifferenceNamesTheKey) {
  nlohmann::json a = {{"time", {{"end", 1.0}}}, {"fluid", {{"rho0", 1000.0}, {"c0", 20.0}}}, {"output", {{"every", 0.1}}}};
  nlohmann::json b = a;
  b["time"]["end"] = 2.0;
  b["output"]["every"] = 0.2;
  EXPECT_EQ(first_physics_difference(a, b), "");
  b["fluid"]["c0"] = 21.0;
  EXPECT_EQ(first_physics_difference(a, b), "fluid.c0");
  b["gravity"] = {0, -9.81};
  EXPECT_EQ(first_physics_difference(a, b), "fluid.c0");
}

TEST(Checkpoint, LastGoodSnapshotRestoresTheStateAndItsCostIsSmall) {
  Simulation<2> sim(tiny());
  StateSnapshot<2> snap;
  snap.capture(sim, {});
  Simulation<2> ref(tiny());
  sim.advance();
  snap.restore(sim);
  EXPECT_TRUE(same_arrays(sim.store(), ref.store()));
  EXPECT_EQ(sim.step(), 0);
  // cost: copy vs step, printed for the record (not asserted: shared machine)
  using clock = std::chrono::steady_clock;
  const int n = 200;
  auto t0 = clock::now();
  for (int k = 0; k < n; ++k) snap.capture(sim, {});
  const double copy = std::chrono::duration<double>(clock::now() - t0).count() / n;
  t0 = clock::now();
  for (int k = 0; k < n; ++k) sim.advance();
  const double step = std::chrono::duration<double>(clock::now() - t0).count() / n;
  std::printf("[ cost     ] last-good copy %.3g s vs step %.3g s (%.2f %%) for %zu particles, %zu bytes\n", copy, step,
              100 * copy / step, sim.size(), snap.bytes());
}
