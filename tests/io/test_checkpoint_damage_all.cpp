// Every single-bit flip of a small checkpoint (validation tier: ~3e5 reads): refused (exit 2) or harmless.
#include "checkpoint_damage.hpp"

using namespace varsph;
using namespace varsph::test;

TEST(CheckpointDamage, EveryBitOfTheFileFlippedIsRefusedOrHarmless) {
  const auto dir = test::scratch_dir("ckpt_flip_all");
  io::Checkpoint ok;
  const std::string bytes = checkpoint_bytes(dir, ok);
  Tally t;
  for (std::size_t pos = 0; pos < bytes.size(); ++pos)
    for (int bit = 0; bit < 8; ++bit) {
      flip_and_read(bytes, dir / "bad.h5", pos, bit, ok, t);
      if (HasFatalFailure()) return;
    }
  std::printf("[ flips    ] %zu-byte checkpoint, all %zu single-bit flips: %ld refused (exit 2), %ld in unread bytes\n",
              bytes.size(), 8 * bytes.size(), t.refused, t.intact);
}

