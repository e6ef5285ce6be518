// --tolerance (study/tolerance.hpp): parsing, name patterns, the cheapest level meeting a tolerance and the
// resolution predicted when none does.
#include <gtest/gtest.h>

#include <cmath>

#include "study/tolerance.hpp"

namespace vs = varsph::study;

TEST(Tolerance, ParsesRelativeAndAbsoluteForms) {
  auto t = vs::parse_tolerance("5%");
  EXPECT_TRUE(t.relative);
  EXPECT_NEAR(t.value, 0.05, 1e-15);
  EXPECT_EQ(t.pattern, "*");
  t = vs::parse_tolerance("p_wall.peak*=500");
  EXPECT_FALSE(t.relative);
  EXPECT_EQ(t.pattern, "p_wall.peak*");
  EXPECT_DOUBLE_EQ(t.value, 500);
  t = vs::parse_tolerance("front_x.*=1%");
  EXPECT_TRUE(t.relative);
  EXPECT_THROW(vs::parse_tolerance("abc"), std::runtime_error);
  EXPECT_THROW(vs::parse_tolerance("x=-1"), std::runtime_error);
  EXPECT_THROW(vs::parse_tolerance("=1"), std::runtime_error);
}

TEST(Tolerance, Glob) {
  EXPECT_TRUE(vs::matches("p_*.peak[*]", "p_wall.peak[0:1]"));
  EXPECT_FALSE(vs::matches("p_*.peak[*]", "p_wall.mean[0:1]"));
  EXPECT_TRUE(vs::matches("*", "anything"));
  EXPECT_TRUE(vs::matches("front_x.*", "front_x.l2[0:1]"));
}

TEST(Tolerance, CheapestLevelAndPredictedResolution) {
  // error bound = h^2 at h = 0.04, 0.02, 0.01 (1.6e-3, 4e-4, 1e-4) on a quantity of scale 1
  vs::Quantity q;
  q.name = "a.mean[0:1]";
  q.scale = 1;
  q.est.bound = {1.6e-3, 4e-4, 1e-4};
  q.est.order_used = 2;
  const std::vector<double> h = {0.04, 0.02, 0.01};
  auto r = vs::evaluate_tolerance(vs::parse_tolerance("0.05%"), {q}, h, 3);
  EXPECT_EQ(r.cheapest_level, 1);
  r = vs::evaluate_tolerance(vs::parse_tolerance("a.*=2.5e-5"), {q}, h, 3);
  EXPECT_EQ(r.cheapest_level, -1);
  ASSERT_EQ(r.quantities.size(), 1u);
  EXPECT_NEAR(r.quantities[0].needed_refined, 0.005, 1e-12);   // h^2 = 2.5e-5
  EXPECT_NEAR(r.quantities[0].needed_cost_factor, 8.0, 1e-9);  // (0.01/0.005)^3
  // a flagged estimate (here: slow convergence) gives no predicted resolution
  q.est.flags = {"observed order 0.2 is below 0.5"};
  q.est.order_used = 0.25;
  r = vs::evaluate_tolerance(vs::parse_tolerance("a.*=2.5e-5"), {q}, h, 3);
  ASSERT_EQ(r.quantities.size(), 1u);
  EXPECT_EQ(r.quantities[0].needed_refined, 0.0);
  EXPECT_EQ(r.quantities[0].needed_cost_factor, 0.0);
  r = vs::evaluate_tolerance(vs::parse_tolerance("b.*=1"), {q}, h, 3);
  EXPECT_TRUE(r.quantities.empty());
  EXPECT_EQ(r.cheapest_level, -1);
}
