// Wave theory for wavemakers (src/waves/): the dispersion relation, Biesel's transfer functions and the
// JONSWAP spectrum against their closed forms and limits; paddle signals (seeded phases, focusing, files,
// ramp) against what they promise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <numbers>
#include <stdexcept>

#include "waves/paddle_signal.hpp"
#include "waves/wave_theory.hpp"

using namespace varsph::waves;

namespace {
constexpr double g = 9.81;
constexpr double pi = std::numbers::pi;
}  // namespace

TEST(Dispersion, SolvesTheRelationTo1e12FromShallowToDeep) {
  for (double h : {0.01, 0.1, 0.5, 2.0, 50.0})
    for (double T : {0.5, 1.0, 2.0, 8.0, 20.0}) {
      const double w = 2 * pi / T, k = wave_number(w, h, g);
      EXPECT_NEAR(g * k * std::tanh(k * h) / (w * w), 1.0, 1e-12) << "h " << h << " T " << T;
    }
}

TEST(Dispersion, DeepAndShallowLimits) {
  // deep water (kh > 20): k = omega^2 / g (tanh = 1 to 1e-17)
  const double w = 2 * pi / 1.0;
  EXPECT_NEAR(wave_number(w, 100.0, g) / (w * w / g), 1.0, 1e-12);
  EXPECT_NEAR(wavelength(1.0, 100.0, g), g / (2 * pi), 1e-12);  // L0 = g T^2 / (2 pi)
  // shallow water: k = omega / sqrt(g h) (1 + (kh)^2 / 6 + O(kh)^4) from tanh x = x - x^3/3 + ...
  const double h = 0.01, ws = 2 * pi / 20.0, ks = wave_number(ws, h, g);
  const double kh = ks * h;
  EXPECT_LT(kh, 0.02);
  EXPECT_NEAR(ks * std::sqrt(g * h) / ws - 1, kh * kh / 6, 1e-9);
}

TEST(Transfer, PistonAndFlapLimits) {
  // shallow water: piston H/S = kh, flap kh / 2; deep water: 2 and 1 (Dean & Dalrymple 1991, fig. 6.4)
  for (double kh : {1e-3, 1e-2}) {
    EXPECT_NEAR(piston_transfer(kh) / kh, 1.0, kh * kh);
    EXPECT_NEAR(flap_transfer(kh) / (kh / 2), 1.0, kh * kh);
  }
  EXPECT_NEAR(piston_transfer(20.0), 2.0, 1e-12);
  // the flap too tends to 2, as 2 (kh - 1) / kh + O(e^-kh) (its motion is all near the surface in deep water)
  EXPECT_NEAR(flap_transfer(20.0), 2 * 19.0 / 20, 1e-8);  // O(kh e^-kh) = 4e-8
  EXPECT_NEAR(flap_transfer(200.0), 2 * 199.0 / 200, 1e-12);
  // a value by hand: kh = 1, piston H/S = 2 (cosh 2 - 1) / (sinh 2 + 2) = 2 (2.762196) / 5.626860 = 0.981789
  EXPECT_NEAR(piston_transfer(1.0), 0.981789, 1e-6);
}

TEST(Transfer, FlapHingedAtAHeightIsTheGeneralPaddleIntegral) {
  const double h = 0.5;
  for (double kh : {0.5, 1.0, 2.5}) {
    const double k = kh / h;
    // hinge on the bed: D&D's formula
    EXPECT_NEAR(flap_transfer(k, h, 0.0), flap_transfer(kh), 1e-14);
    // hinge far below the bed: the paddle translates, a piston
    EXPECT_NEAR(flap_transfer(k, h, -1e5 * h), piston_transfer(kh), 1e-4);
    // hinge at l = 0.3 h and l = -0.4 h: Simpson's rule of 4 sinh kh / (sinh 2kh + 2kh) int f k cosh k(h+z) dz
    for (double l : {0.3 * h, -0.4 * h}) {
      const int n = 20000;
      double sum = 0;
      for (int i = 0; i <= n; ++i) {
        const double z = -h + h * i / n;
        const double f = std::max(0.0, (h + z - l) / (h - l));
        const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
        sum += w * f * k * std::cosh(k * (h + z));
      }
      const double integral = sum * (h / n) / 3;
      EXPECT_NEAR(flap_transfer(k, h, l), 4 * std::sinh(kh) / (std::sinh(2 * kh) + 2 * kh) * integral, 1e-9)
          << "kh " << kh << " l " << l;
    }
  }
}

TEST(Jonswap, ZerothMomentIsHs2Over16AndPeakAtFp) {
  const double Hs = 0.1, Tp = 1.5;
  // gamma = 1 is Pierson-Moskowitz: C = 5/16 in closed form
  EXPECT_NEAR(jonswap_constant(1.0), 5.0 / 16, 1e-12);
  // Goda's fitted constant is within 10 % of the exact normalisation (it targets H1/3, not Hm0)
  for (double gamma : {1.0, 3.3, 7.0}) {
    const double beta = 0.0624 / (0.230 + 0.0336 * gamma - 0.185 / (1.9 + gamma)) * (1.094 - 0.01915 * std::log(gamma));
    EXPECT_NEAR(beta / jonswap_constant(gamma), 1.0, 0.1) << gamma;
  }
  for (double gamma : {1.0, 3.3, 7.0}) {
    // m0 = int_0^inf S df by the midpoint rule on a fine grid (S ~ f^-5 beyond 10 fp: tail < 1e-5 m0)
    const Jonswap S(Hs, Tp, gamma);
    double m0 = 0, fmax_s = 0, smax = 0;
    const double df = 1e-4 / Tp;
    for (double f = df / 2; f < 20 / Tp; f += df) {
      const double s = S(f);
      m0 += s * df;
      if (s > smax) smax = s, fmax_s = f;
    }
    EXPECT_NEAR(m0 / (Hs * Hs / 16), 1.0, 0.01) << "gamma " << gamma;
    EXPECT_NEAR(fmax_s * Tp, 1.0, 0.01) << "gamma " << gamma;
  }
  // the discrete sea a paddle makes (0.5 fp .. 3 fp, 256 bins) holds nearly all of it
  SpectrumSpec s{.Hs = Hs, .Tp = Tp, .gamma = 3.3};
  EXPECT_NEAR(discrete_m0(s) / (Hs * Hs / 16), 1.0, 0.02);
}

TEST(Irregular, SameSeedSameSeaOtherSeedOtherSea) {
  const PaddleGeometry p{.flap = false, .depth = 0.4, .g = g};
  const SpectrumSpec s{.Hs = 0.05, .Tp = 1.2, .gamma = 3.3, .components = 64, .seed = 42};
  const auto a = irregular_waves(p, s), b = irregular_waves(p, s);
  SpectrumSpec s2 = s;
  s2.seed = 43;
  const auto c = irregular_waves(p, s2);
  ASSERT_EQ(a.size(), 64u);
  int differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(std::memcmp(&a[i], &b[i], sizeof(Component)), 0);
    differ += a[i].phase != c[i].phase;
    EXPECT_GE(a[i].phase, 0.0);
    EXPECT_LT(a[i].phase, 2 * pi);
    // stroke amplitude = wave amplitude / transfer function
    const double k = wave_number(a[i].omega, p.depth, g);
    EXPECT_NEAR(a[i].amplitude * piston_transfer(k * p.depth), std::sqrt(2 * jonswap(a[i].omega / (2 * pi), 0.05, 1.2, 3.3) *
                                                                           (2.5 / 1.2) / 64), 1e-15);
  }
  EXPECT_EQ(differ, 64);
  const auto sa = PaddleSignal::sines(a).at(3.7), sb = PaddleSignal::sines(b).at(3.7);
  EXPECT_EQ(std::memcmp(&sa, &sb, sizeof sa), 0);
}

TEST(Focused, CrestsAtTheFocusPointAndTime) {
  const PaddleGeometry p{.flap = true, .depth = 0.5, .hinge_height = 0.1, .g = g};
  const SpectrumSpec s{.Hs = 0.05, .Tp = 1.4, .gamma = 3.3, .components = 48};
  const double A = 0.04, xf = 3.0, tf = 12.0;
  const auto c = focused_group(p, s, A, xf, tf);
  // eta(x, t) = sum_i (X_i H/S_i) cos(omega_i t + phi_i - k_i x)
  auto eta = [&](double x, double t) {
    double e = 0;
    for (const auto& ci : c) {
      const double k = wave_number(ci.omega, p.depth, g);
      e += ci.amplitude * p.transfer(k) * std::cos(ci.omega * t + ci.phase - k * x);
    }
    return e;
  };
  EXPECT_NEAR(eta(xf, tf), A, 1e-12);
  EXPECT_LT(std::abs(eta(xf, tf - 3)), 0.5 * A);
  EXPECT_LT(std::abs(eta(xf - 2, tf)), 0.5 * A);
}

TEST(Regular, StrokeFromHeightAndMadsenOnlyForAPiston) {
  const PaddleGeometry piston{.flap = false, .depth = 0.3, .g = g};
  const double H = 0.03, T = 1.2, k = wave_number(2 * pi / T, 0.3, g);
  const auto c = regular_waves(piston, H, T, 0.0, 1);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(2 * c[0].amplitude * piston_transfer(k * 0.3), H, 1e-15);
  const auto c2 = regular_waves(piston, H, T, 0.0, 2);
  ASSERT_EQ(c2.size(), 2u);
  EXPECT_EQ(c2[1].omega, 2 * c2[0].omega);
  EXPECT_NEAR(c2[1].amplitude, madsen_second_order_amplitude(H, k, 0.3), 1e-18);
  const PaddleGeometry flap{.flap = true, .depth = 0.3, .g = g};
  EXPECT_THROW(regular_waves(flap, H, T, 0.0, 2), std::invalid_argument);
}

TEST(Signal, DerivativesAndRampAreConsistent) {
  auto s = PaddleSignal::sines({{0.02, 5.0, 0.3}, {0.004, 10.0, 0.6}});
  s.set_ramp(2.0);
  EXPECT_EQ(s.at(0).q, 0.0);
  EXPECT_EQ(s.at(0).dq, 0.0);
  const double e = 1e-5;
  for (double t : {0.3, 1.1, 1.9, 2.5, 7.0}) {
    const auto a = s.at(t), m = s.at(t - e), p = s.at(t + e);
    EXPECT_NEAR((p.q - m.q) / (2 * e), a.dq, 1e-8) << t;
    EXPECT_NEAR((p.dq - m.dq) / (2 * e), a.ddq, 1e-6) << t;
  }
  // after the ramp: the plain sum
  EXPECT_NEAR(s.at(7.0).q, 0.02 * std::sin(35.3) + 0.004 * std::sin(70.6), 1e-15);
  EXPECT_NEAR(s.max_abs(), 0.024, 1e-15);
}

TEST(Signal, TableInterpolatesAndRefusesBadRows) {
  const auto s = PaddleSignal::table({0, 1, 3}, {0, 0.1, -0.1});
  EXPECT_NEAR(s.at(0.5).q, 0.05, 1e-15);
  EXPECT_NEAR(s.at(0.5).dq, 0.1, 1e-15);
  EXPECT_NEAR(s.at(2.0).q, 0.0, 1e-15);
  EXPECT_NEAR(s.at(2.0).dq, -0.1, 1e-15);
  EXPECT_EQ(s.at(9.0).q, -0.1);
  EXPECT_EQ(s.at(9.0).dq, 0.0);
  EXPECT_THROW(PaddleSignal::table({0, 1, 1}, {0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(PaddleSignal::table({0, 1, 2}, {0, NAN, 0}), std::invalid_argument);
  const std::string path = testing::TempDir() + "/paddle.csv";
  {
    std::ofstream f(path);
    f << "# lab paddle\ntime,displacement\n0,0\n0.5,0.01\n1.0,0.0\n";
  }
  const auto r = PaddleSignal::read_csv(path);
  EXPECT_NEAR(r.at(0.25).q, 0.005, 1e-15);
  {
    std::ofstream f(path);
    f << "time,displacement\n0,0\n0.5,0.01\n0.5,0.0\n";
  }
  try {
    PaddleSignal::read_csv(path);
    ADD_FAILURE() << "accepted a repeated time";
  } catch (const std::invalid_argument& ex) {
    EXPECT_NE(std::string(ex.what()).find(":4:"), std::string::npos) << ex.what();
  }
  {
    std::ofstream f(path);
    f << "0,0\n0.5,nan\n";
  }
  EXPECT_THROW(PaddleSignal::read_csv(path), std::invalid_argument);
  std::remove(path.c_str());
}
