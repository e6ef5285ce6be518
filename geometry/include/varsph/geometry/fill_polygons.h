#pragma once
#include <Eigen/Core>
#include <vector>
#include "varsph/geometry/read_polylines.h"

namespace varsph::geometry {

// Cell-centred lattice points inside closed 2D loops (even-odd rule, so holes are respected).
// Inputs:
//   loops            closed polylines
//   dx               spacing [m]
//   box_min,box_max  2 each: lattice box; points box_min + (i + 1/2) dx
// Returns #N by 2 positions.
Eigen::MatrixXd fill_polygons(const std::vector<Polyline2>& loops, double dx,
                              const Eigen::Vector2d& box_min, const Eigen::Vector2d& box_max);

// Signed area of a closed loop (> 0 counter-clockwise) [m^2].
double signed_area(const Eigen::MatrixXd& P);

}  // namespace varsph::geometry
