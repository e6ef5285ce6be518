#pragma once
#include <Eigen/Core>
#include <vector>
#include "varsph/geometry/read_polylines.h"

namespace varsph::geometry {

// Boundary particles on 2D polylines and their offset curves.
// Each polyline is split at corners (turn > 30 degrees) and ends; each piece of length l gets
// max(1, round(l/dx)) equal intervals with a particle at every interval end, corners included.
// Layer k is the offset curve at distance k dx on side `side` (arcs around convex corners), sampled
// at ~dx by in-order dart throwing.
// Inputs:
//   lines   polylines (outward normal = right-hand side of the walking direction)
//   dx      spacing [m]; layers >= 1; side +1 outward / -1 inward
// Outputs:
//   X #N by 2 positions, N #N by 2 unit outward normals, A #N length shares [m], L #N layer index
void sample_curves(const std::vector<Polyline2>& lines, double dx, int layers, int side,
                   Eigen::MatrixXd& X, Eigen::MatrixXd& N, Eigen::VectorXd& A, Eigen::VectorXi& L);

}  // namespace varsph::geometry
