// The vectorised pair sweep for AVX2 + FMA (4 doubles per register). This file alone is compiled with
// -mavx2 -mfma (src/CMakeLists.txt); it runs only where the CPU has both (simd/isa.cpp decides).
#include "physics/simd/pack_avx2.hpp"
#include "physics/simd/sweep_kernel.hpp"

namespace varsph::physics::simd {
void sweep_avx2(const SweepArgs& args) { sweep_with<PackAvx2>(args); }
}  // namespace varsph::physics::simd
