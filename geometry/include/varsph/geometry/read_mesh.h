#pragma once
#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace varsph::geometry {

// A repaired triangle mesh.
struct TriangleMesh {
  Eigen::MatrixXd V;          // #V by 3 vertex positions [m] (after the transform)
  Eigen::MatrixXi F;          // #F by 3 vertex indices, consistently oriented (outward if closed)
  int border_edges = 0;       // number of border (one-sided) edges; 0 = closed
  bool self_intersecting = false;  // only computed when read_mesh(..., check_self_intersection)
  double area = 0.0;          // [m^2]
  double volume = 0.0;        // [m^3], 0 when not closed
};

// Reads an STL (ASCII/binary), OBJ, OFF or PLY file, applies `transform` to the vertices and
// repairs it: merges duplicated vertices, removes degenerate faces, orients the faces consistently
// (outward when the mesh is closed), triangulates polygons. Each repair appends a sentence to notes.
// Inputs:
//   path        the file
//   transform   4 by 4 affine transform of the vertices
//   check_self_intersection  run PMP::does_self_intersect (O(#F log #F))
// Outputs:
//   notes       repairs done
//   check_soup_area  optional: called with the area [m^2] of the polygons as read (after the transform,
//               before any repair, which costs O(#F log #F)); it may throw to refuse the file early
// Throws GeometryError on a missing, unreadable, empty or unsupported file, or one that is not a
// polygon mesh after repair.
TriangleMesh read_mesh(const std::filesystem::path& path, const Eigen::Matrix4d& transform,
                       bool check_self_intersection, std::vector<std::string>& notes,
                       const std::function<void(double)>& check_soup_area = nullptr);

}  // namespace varsph::geometry
