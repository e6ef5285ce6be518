#pragma once
// Cubic B-spline kernel (Monaghan & Lattanzio 1985; foundation notes "The cubic spline kernel", k_2 =
// 15/(7 pi h^2) times 2/3 = 10/(7 pi h^2)): W = s_d/h^d {1 - 1.5q^2 + 0.75q^3, q<1; 0.25(2-q)^3, q<2}.
#include <cmath>
#include <numbers>

#include "core/real.hpp"

namespace varsph::kernels {

template <int D>
struct CubicSpline {
  static constexpr const char* name = "cubic_spline";
  static constexpr double kappa = 2.0;

  explicit CubicSpline(double h) : h_(Real(h)), inv_h_(Real(1.0 / h)), sigma_(Real(sigma(h))) {}
  static double sigma(double h) {
    if constexpr (D == 2) return 10.0 / (7.0 * std::numbers::pi * h * h);
    else return 1.0 / (std::numbers::pi * h * h * h);
  }
  VARSPH_HD Real support() const { return Real(kappa) * h_; }
  VARSPH_HD Real h() const { return h_; }
  VARSPH_HD Real w_r2(Real r2) const {
    const Real q = std::sqrt(r2) * inv_h_;
    if (q < Real(1)) return sigma_ * (Real(1) - Real(1.5) * q * q + Real(0.75) * q * q * q);
    const Real t = Real(2) - q;
    return q < Real(2) ? sigma_ * Real(0.25) * t * t * t : Real(0);
  }
  // dW/dr / r: dW/dq = s(-3q + 2.25q^2) for q<1, -0.75 s (2-q)^2 for q<2; divide by h and by r = q h.
  VARSPH_HD Real grad_factor_r2(Real r2) const {
    const Real r = std::sqrt(r2);
    const Real q = r * inv_h_;
    if (q < Real(1)) return sigma_ * (Real(-3) + Real(2.25) * q) * inv_h_ * inv_h_;
    if (q >= Real(2) || r == Real(0)) return Real(0);
    const Real t = Real(2) - q;
    return Real(-0.75) * sigma_ * t * t * inv_h_ / r;
  }

 private:
  Real h_, inv_h_, sigma_;
};

}  // namespace varsph::kernels
