#pragma once
#include <Eigen/Core>

namespace varsph::geometry {

// Indices of the points of `fluid` that are at distance >= min_distance from every point of
// `boundary` (uniform hash grid of cell size min_distance, O(#F + #B)).
// Inputs:
//   fluid         #F by dim (dim 2 or 3)
//   boundary      #B by dim (same dim; may have 0 rows)
//   min_distance  [m]; <= 0 keeps every point
// Returns ascending row indices into fluid.
Eigen::VectorXi points_far_from(const Eigen::MatrixXd& fluid, const Eigen::MatrixXd& boundary,
                                double min_distance);

}  // namespace varsph::geometry
