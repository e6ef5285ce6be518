// Time series of a study (study/time_series.hpp): CSV reading, interpolation, window means, peaks, the common
// time base and norms, against functions whose answers are known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "study/quantities.hpp"
#include "study/time_series.hpp"

namespace vs = varsph::study;

namespace {
vs::Series sampled(double t0, double t1, int n, double (*f)(double)) {
  vs::Series s;
  for (int k = 0; k <= n; ++k) {
    const double t = t0 + (t1 - t0) * k / n;
    s.t.push_back(t);
    s.v.push_back(f(t));
  }
  return s;
}
}  // namespace

TEST(TimeSeries, ReadsCsvWithEmptyCellsAndDropsAPartialLastRow) {
  const auto p = std::filesystem::temp_directory_path() / "varsph_study_table.csv";
  std::ofstream(p) << "time,a,b,c\n0,1,2,\n0.5,3,4,\n1,5";
  const auto t = vs::read_table(p);
  ASSERT_EQ(t.columns.size(), 4u);
  ASSERT_EQ(t.rows(), 2u);
  EXPECT_DOUBLE_EQ((*t.column("b"))[1], 4.0);
  EXPECT_TRUE(std::isnan((*t.column("c"))[0]));
  const auto s = vs::series_of(t, "a");
  EXPECT_EQ(s.t.size(), 2u);
  EXPECT_TRUE(vs::series_of(t, "c").empty());
  EXPECT_TRUE(vs::read_table(p.string() + ".missing").columns.empty());
  std::filesystem::remove(p);
}

TEST(TimeSeries, InterpolatesLinearlyAndNotOutside) {
  const auto s = sampled(0, 1, 4, [](double t) { return 2 * t + 1; });
  EXPECT_NEAR(vs::interpolate(s, 0.3), 1.6, 1e-14);
  EXPECT_TRUE(std::isnan(vs::interpolate(s, 1.2)));
}

TEST(TimeSeries, WindowMeanIsExactForPiecewiseLinearData) {
  const auto s = sampled(0, 1, 10, [](double t) { return t; });
  EXPECT_NEAR(vs::window_mean(s, 0.25, 0.75), 0.5, 1e-14);  // end points interpolated
  EXPECT_NEAR(vs::window_mean(s, 0.0, 2.0), 0.5, 1e-14);    // clipped to the data
}

TEST(TimeSeries, PeakTimeIsRefinedByTheParabola) {
  // an exact parabola with its vertex between samples: the refined time is the vertex
  const auto s = sampled(0, 1, 10, [](double t) { return 5 - 10 * (t - 0.337) * (t - 0.337); });
  const auto p = vs::peak_of(s, 0, 1);
  EXPECT_NEAR(p.time, 0.337, 1e-12);
  EXPECT_NEAR(p.value, 5 - 10 * 0.037 * 0.037, 1e-12);  // the sample's value (not the vertex's)
  EXPECT_FALSE(p.at_edge);
  EXPECT_NEAR(p.sampling, 0.1, 1e-12);
  const auto mono = vs::peak_of(sampled(0, 1, 10, [](double t) { return t; }), 0, 1);
  EXPECT_TRUE(mono.at_edge);
  const auto neg = vs::peak_of(sampled(0, 1, 10, [](double t) { return -3 * std::sin(3.14159265358979 * t); }), 0, 1);
  EXPECT_NEAR(neg.value, -3, 1e-12);  // largest magnitude, sign kept
}

TEST(TimeSeries, CommonGridUsesTheCoarsestSamplingInsideEveryRange) {
  const auto a = sampled(0, 1, 100, [](double t) { return t; });
  const auto b = sampled(0.05, 0.9, 17, [](double t) { return t; });
  const auto g = vs::common_grid({&a, &b}, 0, 1);
  ASSERT_GE(g.size(), 2u);
  EXPECT_NEAR(g.front(), 0.05, 1e-12);
  EXPECT_NEAR(g.back(), 0.9, 1e-12);
  EXPECT_NEAR(g[1] - g[0], 0.05, 1e-9);
}

TEST(TimeSeries, NormsOfADifference) {
  const std::vector<double> a = {1, 2, 3, 4}, b = {1, 2, 3, 2};
  EXPECT_NEAR(vs::norm_of_difference(a, b, vs::Norm::L1), 0.5, 1e-14);
  EXPECT_NEAR(vs::norm_of_difference(a, b, vs::Norm::L2), 1.0, 1e-14);
  EXPECT_NEAR(vs::norm_of_difference(a, b, vs::Norm::Linf), 2.0, 1e-14);
  EXPECT_THROW(vs::parse_norm("l3"), std::runtime_error);
}

TEST(TimeSeries, DifferenceOfTwoRunsOnTheirCommonTimeBase) {
  // series sampled at different times (as levels with different dt are): the distance of f and f + 0.1 is 0.1
  const auto a = sampled(0, 1, 50, [](double t) { return std::sin(t); });
  auto b = sampled(0.003, 0.997, 37, [](double t) { return std::sin(t) + 0.1; });
  vs::Window w{0, 1};
  EXPECT_NEAR(vs::quantity_difference(a, b, vs::Kind::Series, w, vs::Norm::L2), 0.1, 2e-4);
  EXPECT_NEAR(vs::quantity_difference(a, b, vs::Kind::Mean, w, vs::Norm::L2), 0.1, 2e-3);
}
