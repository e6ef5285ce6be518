#pragma once
// Gaussian kernel of the seed paper, eq. (10) and (69), normalised as in PAPER-NOTES.md:
// W(r, h) = s_d / h^d exp(-(r/h)^2) for r <= 3h, 0 beyond; s_d renormalises the truncated integral to 1.
#include <cmath>
#include <numbers>

#include "core/real.hpp"

namespace varsph::kernels {

template <int D>
struct Gaussian {
  static constexpr const char* name = "gaussian";
  static constexpr double kappa = 3.0;  // support radius / h

  explicit Gaussian(double h) : h_(Real(h)), inv_h2_(Real(1.0 / (h * h))), sigma_(Real(sigma(h))) {}

  // Normalisation of the kernel truncated at q = 3 (integral over the disc / ball of radius 3h is 1).
  static double sigma(double h) {
    const double e9 = std::exp(-kappa * kappa);
    if constexpr (D == 2) return 1.0 / (std::numbers::pi * (1.0 - e9) * h * h);
    else
      return 1.0 / (std::pow(std::numbers::pi, 1.5) *
                    (std::erf(kappa) - 2.0 * kappa / std::sqrt(std::numbers::pi) * e9) * h * h * h);
  }

  VARSPH_HD Real support() const { return Real(kappa) * h_; }
  VARSPH_HD Real h() const { return h_; }
  // W as a function of r^2 (r <= support assumed by the caller's cut-off).
  VARSPH_HD Real w_r2(Real r2) const { return sigma_ * std::exp(-r2 * inv_h2_); }
  // F(r) with grad_i W_ij = F * (x_i - x_j): dW/dr / r = -2/h^2 W (seed eq. 24 with R = r/h).
  VARSPH_HD Real grad_factor_r2(Real r2) const { return Real(-2) * inv_h2_ * w_r2(r2); }

 private:
  Real h_, inv_h2_, sigma_;
};

}  // namespace varsph::kernels
