// libFuzzer harness: one mesh format, FUZZ_EXT (".stl", ".obj", ".off", ".ply", ".poly2d"), through
// geometry::sample_body (fuzz_targets.hpp, run_mesh).
#include "fuzz_targets.hpp"

#ifndef FUZZ_EXT
#error "define FUZZ_EXT"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  varsph::fuzz::run_mesh(FUZZ_EXT, data, size);
  return 0;
}
