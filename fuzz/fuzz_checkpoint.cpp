// libFuzzer harness: the checkpoint reader (fuzz_targets.hpp, run_checkpoint).
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  varsph::fuzz::run_checkpoint(data, size);
  return 0;
}
