#pragma once
#include <Eigen/Core>
#include "varsph/geometry/read_mesh.h"
#include "varsph/geometry/read_polylines.h"

namespace varsph::geometry {

// Section of a triangle mesh by a plane (CGAL::Polygon_mesh_slicer), in 2D plane coordinates.
// Inputs:
//   mesh    triangle mesh (V #V by 3, F #F by 3)
//   point   a point of the plane [m]
//   normal  plane normal (any length > 0)
// Returns the section polylines in (u, v) coordinates (see BodyRequest::section_normal), closed
// when the slicer returns a closed polyline, oriented as orient_loops does.
std::vector<Polyline2> slice_mesh(const TriangleMesh& mesh, const Eigen::Vector3d& point,
                                  const Eigen::Vector3d& normal);

// The (u, v) basis used by slice_mesh for a plane normal: rows of a 2 by 3 matrix.
Eigen::Matrix<double, 2, 3> section_basis(const Eigen::Vector3d& normal);

}  // namespace varsph::geometry
