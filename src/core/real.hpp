#pragma once
// The solver's floating-point type, chosen at build time (VARSPH_REAL=double|float) and its vectors.
#include <Eigen/Core>
#include <cstdint>

#include "core/host_device.hpp"

namespace varsph {

#ifdef VARSPH_REAL_FLOAT
using Real = float;
#else
using Real = double;
#endif

template <int D>
using Vec = Eigen::Matrix<Real, D, 1>;

using Index = std::int64_t;

enum class Kind : std::int32_t { Fluid = 0, Boundary = 1 };

}  // namespace varsph
