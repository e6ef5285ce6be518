// points_far_from against an O(N M) brute force.
#include <gtest/gtest.h>

#include <random>

#include "varsph/geometry/points_far_from.h"

using varsph::geometry::points_far_from;

TEST(PointsFarFrom, MatchesBruteForce) {
  for (int dim : {2, 3}) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::MatrixXd fluid(3000, dim), boundary(500, dim);
    for (int i = 0; i < fluid.size(); ++i) fluid.data()[i] = u(rng);
    for (int i = 0; i < boundary.size(); ++i) boundary.data()[i] = u(rng);
    const double d = 0.13;
    const Eigen::VectorXi keep = points_far_from(fluid, boundary, d);
    std::vector<int> brute;
    for (int i = 0; i < fluid.rows(); ++i) {
      bool far = true;
      for (int j = 0; j < boundary.rows() && far; ++j) far = (fluid.row(i) - boundary.row(j)).norm() >= d;
      if (far) brute.push_back(i);
    }
    ASSERT_EQ(keep.size(), static_cast<int>(brute.size())) << dim;
    for (int i = 0; i < keep.size(); ++i) EXPECT_EQ(keep[i], brute[i]);
  }
}

TEST(PointsFarFrom, EmptyBoundaryKeepsAll) {
  Eigen::MatrixXd fluid = Eigen::MatrixXd::Random(10, 3);
  const Eigen::VectorXi keep = points_far_from(fluid, Eigen::MatrixXd(0, 3), 0.1);
  EXPECT_EQ(keep.size(), 10);
}
