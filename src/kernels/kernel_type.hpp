#pragma once
// Kernel selection by name, resolved once at setup; the pair loops are instantiated per kernel type.
#include <string>
#include <string_view>

namespace varsph::kernels {

enum class KernelType { Gaussian, CubicSpline, WendlandC2, PaperLiteral };

inline const char* to_string(KernelType t) {
  switch (t) {
    case KernelType::Gaussian: return "gaussian";
    case KernelType::CubicSpline: return "cubic_spline";
    case KernelType::WendlandC2: return "wendland_c2";
    case KernelType::PaperLiteral: return "paper_literal";
  }
  return "?";
}

inline bool parse_kernel_type(std::string_view s, KernelType& out) {
  for (KernelType t : {KernelType::Gaussian, KernelType::CubicSpline, KernelType::WendlandC2,
                       KernelType::PaperLiteral})
    if (s == to_string(t)) {
      out = t;
      return true;
    }
  return false;
}

// Support radius in units of h.
inline double kappa_of(KernelType t) {
  switch (t) {
    case KernelType::Gaussian: return 3.0;
    case KernelType::CubicSpline: return 2.0;
    case KernelType::WendlandC2: return 2.0;
    case KernelType::PaperLiteral: return 1.0;
  }
  return 2.0;
}

}  // namespace varsph::kernels
