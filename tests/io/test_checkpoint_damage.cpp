// Checkpoints with flipped bits (issue 16): every damaged copy is either refused with an InputError
// (exit 2 on --restart) or reads back exactly the content of the undamaged file (the flip hit bytes
// HDF5 never reads). A crash, another exception or a different state fails. The fast test flips one
// bit in each of 1500 random bytes; test_checkpoint_damage_all (validation tier) flips every bit of the file.
#include <hdf5.h>

#include "checkpoint_damage.hpp"

using namespace varsph;
using namespace varsph::test;



TEST(CheckpointDamage, OneFlippedBitInEachOf1500RandomBytesIsRefusedOrHarmless) {
  const auto dir = test::scratch_dir("ckpt_flip_fast");
  io::Checkpoint ok;
  const std::string bytes = checkpoint_bytes(dir, ok);
  std::mt19937 rng(1600);
  Tally t;
  for (int k = 0; k < 1500; ++k) {
    const std::size_t pos = rng() % bytes.size();
    flip_and_read(bytes, dir / "bad.h5", pos, int(rng() % 8), ok, t);
    if (HasFatalFailure()) return;
  }
  std::printf("[ flips    ] %zu-byte checkpoint, 1500 single-bit flips: %ld refused (exit 2), %ld in unread bytes\n",
              bytes.size(), t.refused, t.intact);
  EXPECT_GT(t.refused, 0);  // the checks see damage at all (the share depends on HDF5's unused space)
  // every identifier the reader opened is closed again, refused files included: what LeakSanitizer still
  // reports after this (HDF5 1.10.8's own blocks lost on damaged files) is suppressed in scripts/lsan.supp
  EXPECT_EQ(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
}

TEST(CheckpointDamage, FormatOneFilesWithoutDigestAreStillRead) {
  // a format-1 checkpoint is read without a digest check (written before the digest existed); the
  // newer-format refusal is tested in test_checkpoint.cpp
  const auto dir = test::scratch_dir("ckpt_v1");
  Simulation<2> sim(scene::parse_scene_json(test::tiny_dam_break(), "tiny.json"));
  sim.advance();
  auto h = checkpoint_header(sim, {});
  h.format_version = 1;
  io::write_checkpoint(dir / "v1.h5", h, sim.store());
  const io::Checkpoint c = io::read_checkpoint(dir / "v1.h5");
  EXPECT_EQ(c.header.format_version, 1);
  EXPECT_EQ(c.header.step, 1);
}
