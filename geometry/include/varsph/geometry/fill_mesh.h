#pragma once
#include <Eigen/Core>
#include "varsph/geometry/read_mesh.h"

namespace varsph::geometry {

// Cell-centred lattice points inside a closed triangle mesh (CGAL::Side_of_triangle_mesh on an AABB
// tree; points on the boundary are left out).
// Inputs:
//   mesh            closed triangle mesh
//   dx              spacing [m]
//   box_min,box_max 3 each: lattice box; points are box_min + (i + 1/2) dx with centres below box_max
// Returns #N by 3 positions.
Eigen::MatrixXd fill_mesh(const TriangleMesh& mesh, double dx, const Eigen::Vector3d& box_min,
                          const Eigen::Vector3d& box_max);

// Which points lie strictly inside a closed triangle mesh (CGAL::Side_of_triangle_mesh on an AABB tree):
// 1 inside, 0 on or outside. Used to clear the fluid from a solid obstacle drawn through it.
// Inputs: mesh (closed), points #N by 3 [m]. Returns #N flags.
Eigen::VectorXi points_inside_mesh(const TriangleMesh& mesh, const Eigen::MatrixXd& points);

}  // namespace varsph::geometry
