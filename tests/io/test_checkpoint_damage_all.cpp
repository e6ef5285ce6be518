// Every single-bit flip of a small checkpoint (validation tier: 8 reads per byte, ~5e5 for a 65 kB file): refused (exit 2) or harmless.
// VARSPH_FLIP_FIRST / VARSPH_FLIP_END (byte offsets, default the whole file) run one range of the campaign, so a
// campaign can be split into pieces and a crash in one piece does not lose the others (docs/reliability.md).
#include <algorithm>
#include <cstdlib>

#include "checkpoint_damage.hpp"

using namespace varsph;
using namespace varsph::test;

TEST(CheckpointDamage, EveryBitOfTheFileFlippedIsRefusedOrHarmless) {
  const auto dir = test::scratch_dir("ckpt_flip_all");
  io::Checkpoint ok;
  const std::string bytes = checkpoint_bytes(dir, ok);
  Tally t;
  const auto env = [](const char* name, std::size_t fallback) {
    const char* v = std::getenv(name);
    return v && *v ? std::size_t(std::strtoull(v, nullptr, 10)) : fallback;
  };
  const std::size_t first = env("VARSPH_FLIP_FIRST", 0), end = std::min(env("VARSPH_FLIP_END", bytes.size()), bytes.size());
  ASSERT_LT(first, end) << "VARSPH_FLIP_FIRST must be below VARSPH_FLIP_END and the file size " << bytes.size();
  for (std::size_t pos = first; pos < end; ++pos) {
    for (int bit = 0; bit < 8; ++bit) {
      flip_and_read(bytes, dir / "bad.h5", pos, bit, ok, t);
      if (HasFatalFailure()) return;
    }
    if ((pos + 1) % 4096 == 0) {  // progress: a run stopped early still tells how far it got
      std::printf("[ flips    ] bytes %zu..%zu of %zu: %ld refused, %ld in unread bytes\n", first, pos, bytes.size(),
                  t.refused, t.intact);
      std::fflush(stdout);
    }
  }
  std::printf("[ flips    ] %zu-byte checkpoint, bytes %zu..%zu, all %zu single-bit flips: %ld refused (exit 2), %ld in unread bytes\n",
              bytes.size(), first, end - 1, 8 * (end - first), t.refused, t.intact);
}

