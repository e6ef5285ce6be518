#include "physics/simd/isa.hpp"

#include <cstdlib>
#include <string>

#include "core/errors.hpp"

namespace varsph::physics::simd {

bool compiled(Isa isa) {
#if defined(VARSPH_SIMD_X86)
  return isa == Isa::Scalar || isa == Isa::Avx2 || isa == Isa::Avx512;
#else
  return isa == Isa::Scalar;
#endif
}

bool cpu_supports(Isa isa) {
  switch (isa) {
    case Isa::Scalar: return true;
#if defined(__x86_64__) || defined(__i386__)
    case Isa::Avx2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case Isa::Avx512: return __builtin_cpu_supports("avx512f");
#else
    default: return false;
#endif
  }
  return false;
}

const char* to_string(Isa isa) {
  switch (isa) {
    case Isa::Scalar: return "scalar";
    case Isa::Avx2: return "avx2";
    case Isa::Avx512: return "avx512";
  }
  return "?";
}

Isa choose_isa() {
  const char* env = std::getenv("VARSPH_SIMD");
  const std::string want = env ? env : "auto";
  if (want.empty() || want == "auto") {
    for (Isa isa : {Isa::Avx512, Isa::Avx2})
      if (compiled(isa) && cpu_supports(isa)) return isa;
    return Isa::Scalar;
  }
  for (Isa isa : {Isa::Scalar, Isa::Avx2, Isa::Avx512}) {
    if (want != to_string(isa)) continue;
    if (!compiled(isa))
      throw InputError("VARSPH_SIMD=" + want + ": this build has no " + want +
                       " sweep (configure with -DVARSPH_SIMD=ON on x86-64)");
    if (!cpu_supports(isa)) throw InputError("VARSPH_SIMD=" + want + ": this CPU does not support " + want);
    return isa;
  }
  throw InputError("VARSPH_SIMD=" + want + ": expected auto, scalar, avx2 or avx512");
}

}  // namespace varsph::physics::simd
