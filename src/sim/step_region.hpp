#pragma once
// Whether a step runs in one OpenMP parallel region (core/team.hpp) or opens one per loop (issue 19
// point 2). VARSPH_STEP_REGION=one (default) | per_loop selects it for A/B runs; both give bitwise the
// same results (test_team).
#include <cstddef>
#include <cstdlib>
#include <string>

#include "core/errors.hpp"

namespace varsph {

enum class StepRegion { One, PerLoop };

inline StepRegion step_region_mode() {
  const char* e = std::getenv("VARSPH_STEP_REGION");
  if (!e) return StepRegion::One;
  const std::string v(e);
  if (v == "one") return StepRegion::One;
  if (v == "per_loop") return StepRegion::PerLoop;
  throw InputError("VARSPH_STEP_REGION=" + v + ": expected one or per_loop");
}

// Above this many particles (owned + ghosts) a loop's work dwarfs a fork/join (~2-4 us against >= 50 us
// per loop on 2 threads), and the grid's counting sort runs in parallel (neighbor_grid.cpp,
// kParallelSortMin), which inside one region would run on one thread: the step opens a region per loop.
inline constexpr std::size_t kOneRegionMax = 100000;

}  // namespace varsph
