#pragma once
// Which pair sweep runs: the scalar one (the reference, and every combination the vector code does not
// cover) or the vectorised one for the best instruction set this build has and this CPU supports.
// VARSPH_SIMD=auto|scalar|avx2|avx512 in the environment overrides the choice (benchmarks, tests).
#include "physics/simd/sweep_args.hpp"

namespace varsph::physics::simd {

// Sweeps compiled into this build (CMake option VARSPH_SIMD, x86-64 only).
bool compiled(Isa isa);
// Instruction sets of this CPU (cpuid through __builtin_cpu_supports).
bool cpu_supports(Isa isa);
// The choice for a new Rates object: VARSPH_SIMD if set (InputError naming the variable when the value is
// unknown or the build/CPU lacks it), else the best compiled and supported one.
Isa choose_isa();
const char* to_string(Isa isa);

}  // namespace varsph::physics::simd
