// libFuzzer harness: one mesh format, FUZZ_EXT (".stl", ".obj", ".off", ".ply", ".poly2d"), through
// geometry::sample_body (fuzz_targets.hpp, run_mesh); with FUZZ_READER_ALONE, through its reader alone
// (run_mesh_read: no sampling, about 13x the inputs per second; fuzz_<fmt>_read).
#include "fuzz_targets.hpp"

#ifndef FUZZ_EXT
#error "define FUZZ_EXT"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
#ifdef FUZZ_READER_ALONE
  varsph::fuzz::run_mesh_read(FUZZ_EXT, data, size);
#else
  varsph::fuzz::run_mesh(FUZZ_EXT, data, size);
#endif
  return 0;
}
