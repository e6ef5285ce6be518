#pragma once
#include <Eigen/Core>
#include <filesystem>
#include <vector>

namespace varsph::geometry {

// One 2D polyline.
struct Polyline2 {
  Eigen::MatrixXd P;    // #P by 2 vertex positions [m]; a closed loop does not repeat its first point
  bool closed = true;
};

// Reads a .poly2d file (docs/geometry.md): one "x y" per line, '#' starts a comment, a blank line
// ends a loop, a line "open" inside a loop makes it an open polyline. Applies `transform` to
// (x, y, 0, 1). Closed loops are re-oriented so that outer loops run counter-clockwise and holes
// (loops inside an odd number of other loops) clockwise, so that the outward normal is the
// right-hand side (t_y, -t_x) of the walking direction; a note records each reversal.
// Throws GeometryError naming file and line on a malformed line, or an empty/missing file.
std::vector<Polyline2> read_polylines(const std::filesystem::path& path,
                                      const Eigen::Matrix4d& transform,
                                      std::vector<std::string>& notes);

// Orients closed loops as read_polylines does (outer CCW, holes CW); returns the number reversed.
int orient_loops(std::vector<Polyline2>& loops);

}  // namespace varsph::geometry
