// The vectorised pair sweep for AVX-512F (8 doubles per register). This file alone is compiled with
// -mavx512f (src/CMakeLists.txt); it runs only where the CPU has it (simd/isa.cpp decides).
#include "physics/simd/pack_avx512.hpp"
#include "physics/simd/sweep_kernel.hpp"

namespace varsph::physics::simd {
void sweep_avx512(const SweepArgs& args) { sweep_with<PackAvx512>(args); }
}  // namespace varsph::physics::simd
