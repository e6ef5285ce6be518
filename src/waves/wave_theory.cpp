#include "waves/wave_theory.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

namespace varsph::waves {

double wave_number(double omega, double depth, double g) {
  if (!(omega > 0) || !(depth > 0) || !(g > 0)) throw std::invalid_argument("wave_number: omega, depth and g must be > 0");
  // Fenton & McKee (1990) explicit approximation: kh ~ k0 h coth((k0 h)^(3/4))^(2/3), k0 = omega^2 / g
  const double k0h = omega * omega * depth / g;
  double kh = k0h * std::pow(1.0 / std::tanh(std::pow(k0h, 0.75)), 2.0 / 3.0);
  // Newton on F(kh) = kh tanh(kh) - k0 h (dispersion relation times h / g)
  for (int it = 0; it < 50; ++it) {
    const double t = std::tanh(kh);
    const double F = kh * t - k0h;
    const double dF = t + kh * (1 - t * t);
    const double step = F / dF;
    kh -= step;
    if (std::abs(step) <= 1e-15 * kh) break;
  }
  return kh / depth;
}

double wavelength(double period, double depth, double g) {
  if (!(period > 0)) throw std::invalid_argument("wavelength: period must be > 0");
  return 2 * std::numbers::pi / wave_number(2 * std::numbers::pi / period, depth, g);
}

double piston_transfer(double kh) {
  return 2 * (std::cosh(2 * kh) - 1) / (std::sinh(2 * kh) + 2 * kh);  // Biesel; D&D 1991 eq. 6.19
}

double flap_transfer(double kh) {
  // D&D 1991 eq. 6.21
  return 4 * (std::sinh(kh) / kh) * (kh * std::sinh(kh) - std::cosh(kh) + 1) / (std::sinh(2 * kh) + 2 * kh);
}

double flap_transfer(double k, double depth, double hinge_height) {
  const double kh = k * depth, arm = k * (depth - hinge_height);  // k (h - l): the flap's wetted arm
  if (!(arm > 0)) throw std::invalid_argument("flap_transfer: the hinge must lie below the still-water level");
  // general paddle integral (wave_theory.hpp): int f k cosh k(h+z) dz over the flap's moving part
  const double integral = (arm * std::sinh(kh) - std::cosh(kh) + std::cosh(k * std::max(hinge_height, 0.0))) / arm;
  return 4 * std::sinh(kh) / (std::sinh(2 * kh) + 2 * kh) * integral;
}

double madsen_second_order_amplitude(double H, double k, double depth) {
  const double kh = k * depth, s = std::sinh(kh);
  const double m1 = piston_transfer(kh);
  return H * H / (32 * depth) * (3 * std::cosh(kh) / (s * s * s) - 2 / m1);  // Madsen 1971; Altomare 2017 eq. 8
}

double miche_limit(double kh) { return 0.142 * std::tanh(kh); }

double jonswap_constant(double gamma) {
  if (!(gamma >= 1)) throw std::invalid_argument("jonswap: gamma must be >= 1");
  // the peak part: (gamma^r - 1) vanishes to 1e-30 outside 0.4 < u < 2 (r < e^-60 there); Simpson's rule
  const double a = 0.4, b = 2.0;
  const int n = 8000;
  auto g = [&](double u) {
    const double sigma = u <= 1 ? 0.07 : 0.09;
    const double r = std::exp(-(u - 1) * (u - 1) / (2 * sigma * sigma));
    return std::pow(u, -5) * std::exp(-1.25 / std::pow(u, 4)) * (std::pow(gamma, r) - 1);
  };
  double sum = g(a) + g(b);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4 : 2) * g(a + (b - a) * i / n);
  const double I = 0.2 + sum * (b - a) / n / 3;
  return 1 / (16 * I);
}

Jonswap::Jonswap(double Hs_, double Tp_, double gamma_) : Hs(Hs_), Tp(Tp_), gamma(gamma_), C(jonswap_constant(gamma_)) {}

double Jonswap::operator()(double f) const {
  if (!(f > 0)) return 0;
  const double fp = 1 / Tp;
  const double sigma = f <= fp ? 0.07 : 0.09;
  const double tf = Tp * f;
  const double r = std::exp(-(tf - 1) * (tf - 1) / (2 * sigma * sigma));
  // Goda (1988) form: S(f) = C Hs^2 Tp^-4 f^-5 exp(-1.25 (Tp f)^-4) gamma^r
  return C * Hs * Hs / std::pow(Tp, 4) / std::pow(f, 5) * std::exp(-1.25 / std::pow(tf, 4)) * std::pow(gamma, r);
}

double jonswap(double f, double Hs, double Tp, double gamma) { return Jonswap(Hs, Tp, gamma)(f); }

struct SeededUniform::Impl {
  std::mt19937_64 engine;
};

SeededUniform::SeededUniform(std::uint64_t seed) : impl_(new Impl{std::mt19937_64(seed)}) {}
SeededUniform::~SeededUniform() { delete impl_; }
double SeededUniform::next() { return double(impl_->engine() >> 11) * 0x1.0p-53; }

}  // namespace varsph::waves
