#pragma once
// The seed paper's kernel taken literally, eq. (10), (24), (69): W(r) = l exp(-r^2) for r <= h, with r
// in metres and grad W = -2 l exp(-r^2) x_ij. Not normalised (PAPER-NOTES.md); kept so the paper's
// h = 0.072, l = 9.47 can be tried (`--set kernel.type=paper_literal`). Not for production runs.
#include <cmath>

#include "core/real.hpp"

namespace varsph::kernels {

template <int D>
struct PaperLiteral {
  static constexpr const char* name = "paper_literal";
  static constexpr double kappa = 1.0;

  PaperLiteral(double h, double l) : h_(Real(h)), l_(Real(l)) {}
  VARSPH_HD Real support() const { return h_; }
  VARSPH_HD Real h() const { return h_; }
  VARSPH_HD Real w_r2(Real r2) const { return l_ * std::exp(-r2); }
  VARSPH_HD Real grad_factor_r2(Real r2) const { return Real(-2) * l_ * std::exp(-r2); }

 private:
  Real h_, l_;
};

}  // namespace varsph::kernels
