#pragma once
// Tolerances for tests that compare quantities computed in Real (double or float, core/real.hpp).
// Rule (issue 9): tolerances of 1e-9 and tighter hold for the double build only; in the float build a test
// derives its tolerance from float's machine epsilon instead of being disabled.
#include <algorithm>
#include <limits>
#include <type_traits>

#include "core/real.hpp"

namespace varsph::test {

inline constexpr bool kRealIsDouble = std::is_same_v<Real, double>;
inline constexpr double kRealEps = double(std::numeric_limits<Real>::epsilon());

// `double_tol` in the double build; in the float build max(double_tol, ulps * eps(float) * scale), where
// `ulps` says how many roundings the checked quantity accumulates and `scale` its magnitude.
inline double real_tol(double double_tol, double ulps, double scale = 1.0) {
  if constexpr (kRealIsDouble) return double_tol;
  else return std::max(double_tol, ulps * kRealEps * scale);
}

}  // namespace varsph::test
