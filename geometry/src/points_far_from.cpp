#include "varsph/geometry/points_far_from.h"

#include <stdexcept>
#include <vector>

#include "detail/point_grid.h"

namespace varsph::geometry {

Eigen::VectorXi points_far_from(const Eigen::MatrixXd& fluid, const Eigen::MatrixXd& boundary,
                                double min_distance) {
  const Eigen::Index n = fluid.rows();
  if (min_distance <= 0 || boundary.rows() == 0) return Eigen::VectorXi::LinSpaced(n, 0, static_cast<int>(n) - 1);
  if (boundary.cols() != fluid.cols())
    throw std::invalid_argument("points_far_from: fluid and boundary have different dimensions");
  auto row3 = [](const Eigen::MatrixXd& M, Eigen::Index i) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (Eigen::Index c = 0; c < M.cols() && c < 3; ++c) p[c] = M(i, c);
    return p;
  };
  detail::PointGrid grid(2.0 * min_distance);
  grid.reserve(static_cast<std::size_t>(boundary.rows()));
  for (Eigen::Index i = 0; i < boundary.rows(); ++i) grid.insert(row3(boundary, i));
  std::vector<int> keep;
  keep.reserve(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i)
    if (!grid.any_within(row3(fluid, i), min_distance)) keep.push_back(static_cast<int>(i));
  return Eigen::Map<Eigen::VectorXi>(keep.data(), static_cast<Eigen::Index>(keep.size()));
}

}  // namespace varsph::geometry
