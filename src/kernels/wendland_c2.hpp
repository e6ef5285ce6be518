#pragma once
// Wendland C2 kernel (Wendland 1995; foundation notes "The Wendland C2 kernel"):
// W = s_d/h^d (1 - q/2)^4 (2q + 1), q < 2, with s_2 = 7/(4 pi) and s_3 = 21/(16 pi)
// (the notes' 21/(2 pi) is a typo, PAPER-NOTES.md; the normalisation test integrates W).
#include <cmath>
#include <numbers>

#include "core/real.hpp"

namespace varsph::kernels {

template <int D>
struct WendlandC2 {
  static constexpr const char* name = "wendland_c2";
  static constexpr double kappa = 2.0;

  explicit WendlandC2(double h) : h_(Real(h)), inv_h_(Real(1.0 / h)), sigma_(Real(sigma(h))) {}
  static double sigma(double h) {
    if constexpr (D == 2) return 7.0 / (4.0 * std::numbers::pi * h * h);
    else return 21.0 / (16.0 * std::numbers::pi * h * h * h);
  }
  VARSPH_HD Real support() const { return Real(kappa) * h_; }
  VARSPH_HD Real h() const { return h_; }
  VARSPH_HD Real w_r2(Real r2) const {
    const Real q = std::sqrt(r2) * inv_h_;
    if (q >= Real(2)) return Real(0);
    const Real t = Real(1) - Real(0.5) * q;
    const Real t2 = t * t;
    return sigma_ * t2 * t2 * (Real(2) * q + Real(1));
  }
  // dW/dq = -5 q (1 - q/2)^3 s; grad factor = dW/dq / (h r) = -5 s (1 - q/2)^3 / h^2.
  VARSPH_HD Real grad_factor_r2(Real r2) const {
    const Real q = std::sqrt(r2) * inv_h_;
    if (q >= Real(2)) return Real(0);
    const Real t = Real(1) - Real(0.5) * q;
    return Real(-5) * sigma_ * t * t * t * inv_h_ * inv_h_;
  }

 private:
  Real h_, inv_h_, sigma_;
};

}  // namespace varsph::kernels
