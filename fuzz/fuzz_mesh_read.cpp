// libFuzzer harness: one mesh format's reader alone, FUZZ_EXT (".stl", ".obj", ".off", ".ply"), through
// geometry::read_mesh (fuzz_targets.hpp, run_mesh_read); fuzz_mesh.cpp goes on into the samplers.
#include "fuzz_targets.hpp"

#ifndef FUZZ_EXT
#error "define FUZZ_EXT"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  varsph::fuzz::run_mesh_read(FUZZ_EXT, data, size);
  return 0;
}
