#pragma once
// Shared by the checkpoint damage tests: a small checkpoint, one flipped bit, and the verdict.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>

#include "core/errors.hpp"
#include "io/checkpoint.hpp"
#include "results_scenes.hpp"
#include "scene/scene.hpp"
#include "sim/restart.hpp"
#include "sim/simulation.hpp"
#include "test_support.hpp"

namespace varsph::test {
namespace fs = std::filesystem;

inline bool same(const io::Checkpoint& a, const io::Checkpoint& b) {
  const auto& x = a.header;
  const auto& y = b.header;
  if (x.format_version != y.format_version || x.program_version != y.program_version || x.real_type != y.real_type ||
      x.dimension != y.dimension || x.step != y.step || std::memcmp(&x.time, &y.time, sizeof x.time) != 0 ||
      std::memcmp(&x.dt, &y.dt, sizeof x.dt) != 0 || x.particles != y.particles || x.scene != y.scene ||
      x.integrator != y.integrator || x.integrator_state != y.integrator_state || x.runner_state != y.runner_state ||
      a.arrays.size() != b.arrays.size())
    return false;
  for (std::size_t k = 0; k < a.arrays.size(); ++k)
    if (a.arrays[k].name != b.arrays[k].name || a.arrays[k].type != b.arrays[k].type ||
        a.arrays[k].components != b.arrays[k].components || a.arrays[k].bytes != b.arrays[k].bytes)
      return false;
  return true;
}

struct Tally {
  long refused = 0, intact = 0;
};

// flips bit `bit` of byte `pos` of `good` into `bad`, reads it, classifies
inline void flip_and_read(const std::string& good_bytes, const fs::path& bad, std::size_t pos, int bit,
                   const io::Checkpoint& ok, Tally& t) {
  std::string b = good_bytes;
  b[pos] = char(b[pos] ^ (1 << bit));
  fs::remove(bad);  // a new file, not a truncated one: ext4 flushes a file truncated and rewritten (auto_da_alloc) at close
  std::ofstream(bad, std::ios::binary) << b;
  try {
    const io::Checkpoint c = io::read_checkpoint(bad);
    ASSERT_TRUE(same(c, ok)) << "byte " << pos << " bit " << bit << ": damaged file read as a different state";
    ++t.intact;
  } catch (const InputError& e) {
    ++t.refused;
    ASSERT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
  }
}

inline std::string checkpoint_bytes(const fs::path& dir, io::Checkpoint& ok) {
  Simulation<2> sim(scene::parse_scene_json(test::tiny_dam_break(), "tiny.json"));
  for (int k = 0; k < 5; ++k) sim.advance();
  const auto good = dir / "good.h5";
  io::write_checkpoint(good, checkpoint_header(sim, {{"frame_index", 1}}), sim.store());
  ok = io::read_checkpoint(good);
  std::ifstream in(good, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}


}  // namespace varsph::test
