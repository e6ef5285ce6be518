#pragma once
// Build options recorded in run.json and printed by `varsph --version`.
#include <nlohmann/json.hpp>

namespace varsph {

inline nlohmann::json build_info() {
  return {{"version", VARSPH_VERSION},
          {"real", VARSPH_REAL_NAME},
          {"native", bool(VARSPH_NATIVE_BUILD)},
          {"build_type", VARSPH_BUILD_TYPE},
          {"compiler", __VERSION__},
          {"openmp", _OPENMP},
          {"mpi", bool(VARSPH_MPI_BUILD)},
          {"cuda", bool(VARSPH_HAVE_CUDA_BUILD)}};  // the CUDA backend is compiled in (docs/gpu.md)
}

}  // namespace varsph
