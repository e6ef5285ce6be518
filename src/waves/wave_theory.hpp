#pragma once
// Linear wave theory for wavemakers: pure functions, no solver state (docs/waves.md).
//   dispersion       omega^2 = g k tanh(k h)                                  (Dean & Dalrymple 1991, eq. 4.20)
//   piston           H/S = 2 (cosh 2kh - 1) / (sinh 2kh + 2kh)                 (Biesel 1951; D&D 1991 eq. 6.19)
//   flap (bed hinge) H/S = 4 (sinh kh / kh) (kh sinh kh - cosh kh + 1) / (sinh 2kh + 2kh)   (D&D 1991 eq. 6.21)
// S is the paddle's stroke (peak to peak) at the still-water level, H the progressive wave's height far from
// the paddle (the evanescent modes have decayed: about two depths).
// The general paddle whose displacement is X(z) = (S/2) f(z), f(0) = 1, z up from the still-water level,
// gives (D&D 1991 eq. 6.11-6.18 with the progressive mode's coefficient):
//   H/S = 4 sinh kh / (sinh 2kh + 2kh) * int_{-h}^{0} f(z) k cosh k(h + z) dz
// which for a flap hinged at a height l above the bed (f = (h + z - l)/(h - l) above the hinge, 0 below it:
// the part under the hinge is a fixed wall) and for a hinge below the bed (l < 0: f linear over the whole depth)
// integrates to
//   H/S = 4 sinh kh / (sinh 2kh + 2kh) * [k(h - l) sinh kh - cosh kh + cosh(k max(l, 0))] / (k (h - l))
// l = 0 is D&D's bed-hinged flap, l -> -inf the piston (Hughes 1993, Physical Models and Laboratory
// Techniques in Coastal Engineering, section 8.2, gives the same family).
#include <cstdint>

namespace varsph::waves {

inline constexpr double kGravity = 9.81;

// Wave number k [rad/m] of the linear dispersion relation for angular frequency omega [rad/s] in depth h [m],
// by Newton's method from Fenton & McKee's (1990) explicit start; |residual| <= 1e-12 relative.
double wave_number(double omega, double depth, double g = kGravity);
// Wavelength L = 2 pi / k [m] of period T [s].
double wavelength(double period, double depth, double g = kGravity);

// Biesel transfer functions H/S of kh (> 0). hinge_height l [m] above the bed (negative: below), depth h [m].
double piston_transfer(double kh);
double flap_transfer(double kh);
double flap_transfer(double k, double depth, double hinge_height);

// Madsen (1971) second-order correction of a piston's regular-wave motion, the amplitude of the sin(2 omega t)
// term that cancels the free second harmonic (as written in Altomare et al. 2017, Coastal Eng. 127, eq. 8):
//   X2 = H^2 / (32 h) (3 cosh kh / sinh^3 kh - 2 / m1),  m1 = H/S the piston transfer function.
double madsen_second_order_amplitude(double H, double k, double depth);

// Miche (1944) breaking limit of the steepness, H/L <= 0.142 tanh(kh), and the depth-limited H/h <= 0.78
// (McCowan 1894).
double miche_limit(double kh);
inline constexpr double kDepthBreakingLimit = 0.78;

// JONSWAP spectral density S(f) [m^2/Hz] (Hasselmann et al. 1973) in Goda's (1988) form with significant
// height Hs = Hm0 = 4 sqrt(m0) [m], peak period Tp [s] and peak enhancement gamma:
//   S(f) = C(gamma) Hs^2 Tp^-4 f^-5 exp(-1.25 (Tp f)^-4) gamma^exp(-(Tp f - 1)^2 / (2 sigma^2)),
//   sigma = 0.07 (f <= fp), 0.09 (f > fp).
// C(gamma) makes m0 = Hs^2 / 16 exactly: C = 1 / (16 I), I = int_0^inf u^-5 exp(-1.25 u^-4) gamma^r(u) du
// = 1/5 + int u^-5 exp(-1.25 u^-4) (gamma^r - 1) du (the first part in closed form: d/du exp(-1.25 u^-4)
// = 5 u^-5 exp(-1.25 u^-4); so C(1) = 5/16, Pierson-Moskowitz). Goda's fitted beta_J = 0.0624 / (0.230 +
// 0.0336 gamma - 0.185 / (1.9 + gamma)) (1.094 - 0.01915 ln gamma) is 6-9 % larger: it is fitted to H1/3.
double jonswap_constant(double gamma);
struct Jonswap {
  double Hs = 0, Tp = 0, gamma = 3.3;
  double C = 0;  // jonswap_constant(gamma)
  Jonswap(double Hs_, double Tp_, double gamma_);
  double operator()(double f) const;
};
double jonswap(double f, double Hs, double Tp, double gamma);  // one-off evaluation (computes C)

// Uniform random numbers in [0, 1) from a seed, the same on every platform (std::mt19937_64 is specified
// bit for bit; the standard's distributions are not, so the 53 top bits are scaled here).
class SeededUniform {
 public:
  explicit SeededUniform(std::uint64_t seed);
  ~SeededUniform();
  SeededUniform(const SeededUniform&) = delete;
  SeededUniform& operator=(const SeededUniform&) = delete;
  double next();

 private:
  struct Impl;
  Impl* impl_;
};

}  // namespace varsph::waves
