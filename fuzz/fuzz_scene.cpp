// libFuzzer harness: the scene reader with --set overrides (fuzz_targets.hpp, run_scene).
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  varsph::fuzz::run_scene(data, size);
  return 0;
}
