// Observed order, Richardson extrapolation and the flags of study/richardson.hpp on sequences with a known
// converged value (Celik et al. 2008 procedure; Roache 1998 safety factors).
#include <gtest/gtest.h>

#include <cmath>

#include "study/richardson.hpp"

namespace vs = varsph::study;

namespace {
bool has_flag(const vs::OrderEstimate& e, const std::string& word) {
  for (const auto& f : e.flags)
    if (f.find(word) != std::string::npos) return true;
  return false;
}
std::vector<double> values(const std::vector<double>& h, double (*f)(double)) {
  std::vector<double> v;
  for (double x : h) v.push_back(f(x));
  return v;
}
}  // namespace

TEST(Richardson, PowerLawGivesItsOrderAndLimit) {
  const std::vector<double> h = {0.04, 0.02, 0.01};
  const auto phi = values(h, [](double x) { return 1.0 + 0.5 * x * x; });
  const auto e = vs::richardson(h, phi, 2.0, 1e-15);
  EXPECT_TRUE(e.trusted());
  EXPECT_NEAR(e.order, 2.0, 1e-9);
  EXPECT_NEAR(e.extrapolated, 1.0, 1e-12);
  for (std::size_t k = 0; k < h.size(); ++k) EXPECT_NEAR(e.error[k], 0.5 * h[k] * h[k], 1e-12);
  EXPECT_DOUBLE_EQ(e.safety, 1.25);
  EXPECT_NEAR(e.bound[2], 1.25 * 0.5e-4, 1e-12);
  EXPECT_NEAR(e.order_fit, 2.0, 1e-9);
}

TEST(Richardson, UnequalRatiosRecoverTheOrder) {
  // Celik et al. 2008 eq. (3)-(4): r21 != r32 needs the fixed-point iteration
  const std::vector<double> h = {0.04, 0.025, 0.01};
  const auto phi = values(h, [](double x) { return 3.0 - 2.0 * std::pow(x, 1.5); });
  const auto e = vs::richardson(h, phi, 2.0, 1e-15);
  EXPECT_NEAR(e.order, 1.5, 1e-8);
  EXPECT_TRUE(e.trusted());
  EXPECT_NEAR(e.extrapolated, 3.0, 1e-10);
  EXPECT_NEAR(vs::three_level_order(phi[1] - phi[2], phi[0] - phi[1], 2.5, 1.6), 1.5, 1e-8);
}

TEST(Richardson, HigherOrderTermsStayInsideTheBound) {
  // phi = 1 + h^2 + 20 h^3: the three-level estimate is not exact, the defended bound still covers the truth
  const std::vector<double> h = {0.04, 0.02, 0.01};
  const auto phi = values(h, [](double x) { return 1.0 + x * x + 20 * x * x * x; });
  const auto e = vs::richardson(h, phi, 2.0, 1e-15);
  for (std::size_t k = 0; k < h.size(); ++k) {
    const double truth = std::abs(phi[k] - 1.0);
    EXPECT_LE(truth, e.bound[k]) << "level " << k;
    EXPECT_GE(e.error[k], truth / 3) << "level " << k;
  }
}

TEST(Richardson, OscillatoryConvergenceIsFlaggedAndBoundedByTheRange) {
  const std::vector<double> h = {0.04, 0.02, 0.01};
  const std::vector<double> phi = {1.0, 1.1, 1.05};
  const auto e = vs::richardson(h, phi, 2.0, 1e-15);
  EXPECT_FALSE(e.trusted());
  EXPECT_TRUE(has_flag(e, "oscillatory"));
  EXPECT_TRUE(std::isnan(e.extrapolated));
  EXPECT_NEAR(e.error[2], 0.1, 1e-12);  // the largest level difference
  EXPECT_DOUBLE_EQ(e.safety, 3.0);
}

TEST(Richardson, GrowingDifferencesAreFlaggedAsNotConverging) {
  const std::vector<double> h = {0.04, 0.02, 0.01};
  const std::vector<double> phi = {1.0, 1.01, 1.05};
  const auto e = vs::richardson(h, phi, 2.0, 1e-15);
  EXPECT_TRUE(has_flag(e, "grow"));
  EXPECT_LT(e.order, 0);
  EXPECT_NEAR(e.error[2], 0.04, 1e-12);
}

TEST(Richardson, OrderFarAboveTheSchemeIsFlaggedAndCapped) {
  const std::vector<double> h = {0.4, 0.2, 0.1};
  const auto phi = values(h, [](double x) { return 2.0 + std::pow(x, 5); });
  const auto e = vs::richardson(h, phi, 2.0, 1e-15);
  EXPECT_NEAR(e.order, 5.0, 1e-8);
  EXPECT_DOUBLE_EQ(e.order_used, 2.0);
  EXPECT_TRUE(has_flag(e, "far above"));
  EXPECT_LE(std::abs(phi[2] - 2.0), e.bound[2]);  // capping makes the bound conservative
}

TEST(Richardson, SlowOrderIsFlagged) {
  const std::vector<double> h = {0.04, 0.02, 0.01};
  const auto phi = values(h, [](double x) { return std::pow(x, 0.3); });
  const auto e = vs::richardson(h, phi, 2.0, 1e-15);
  EXPECT_NEAR(e.order, 0.3, 1e-8);
  EXPECT_TRUE(has_flag(e, "below 0.5"));
}

TEST(Richardson, NoChangeIsANoteNotAFlag) {
  const std::vector<double> h = {0.04, 0.02, 0.01};
  const auto e = vs::richardson(h, {5.0, 5.0, 5.0}, 2.0, 1e-9);
  EXPECT_TRUE(e.trusted());
  EXPECT_EQ(e.notes.size(), 1u);
  EXPECT_DOUBLE_EQ(e.extrapolated, 5.0);
  EXPECT_LE(e.error[0], 1e-9);
}

TEST(Richardson, TwoLevelsUseTheFormalOrderWithSafetyThree) {
  const auto e = vs::richardson({0.02, 0.01}, {1.0004, 1.0001}, 2.0, 1e-15);
  EXPECT_TRUE(has_flag(e, "two levels"));
  EXPECT_NEAR(e.extrapolated, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(e.safety, 3.0);
}

TEST(Richardson, FailedLevelIsFlagged) {
  const double nan = std::nan("");
  const auto e = vs::richardson({0.04, 0.02, 0.01}, {1.0016, 1.0004, nan}, 2.0, 1e-15);
  EXPECT_TRUE(has_flag(e, "without a value"));
  EXPECT_TRUE(std::isnan(e.error[2]));
  EXPECT_TRUE(std::isfinite(e.error[1]));
}

TEST(Richardson, FourLevelsOutsideTheAsymptoticRangeAreFlagged) {
  // differences 0.1, 0.05 (order 1), then 0.0125 (order 2): the last triple is used, the change flagged
  const std::vector<double> h = {0.08, 0.04, 0.02, 0.01};
  const std::vector<double> phi = {1.1 + 0.05 + 0.0125, 1.05 + 0.0125, 1.0125, 1.0};
  const auto e = vs::richardson(h, phi, 2.0, 1e-15);
  ASSERT_EQ(e.orders.size(), 2u);
  EXPECT_NEAR(e.orders[0], 1.0, 1e-9);
  EXPECT_NEAR(e.orders[1], 2.0, 1e-9);
  EXPECT_TRUE(has_flag(e, "asymptotic"));
}

TEST(Richardson, SeriesDifferencesGiveTheOrder) {
  // f_k(t) = sin t + h_k^2 g(t): ||f_k - f_k+1|| = (h_k^2 - h_k+1^2) ||g||
  const std::vector<double> h = {0.04, 0.02, 0.01};
  std::vector<double> d;
  for (std::size_t k = 0; k + 1 < h.size(); ++k) d.push_back((h[k] * h[k] - h[k + 1] * h[k + 1]) * 0.7);
  const auto e = vs::richardson_of_differences(h, d, 2.0, 1e-15);
  EXPECT_NEAR(e.order, 2.0, 1e-9);
  EXPECT_TRUE(e.trusted());
  EXPECT_NEAR(e.error[2], 0.7 * h[2] * h[2], 1e-12);
}

TEST(Richardson, LogLogSlope) {
  EXPECT_NEAR(vs::log_log_slope({1, 2, 4}, {3, 12, 48}), 2.0, 1e-12);
  EXPECT_TRUE(std::isnan(vs::log_log_slope({1}, {1})));
}
