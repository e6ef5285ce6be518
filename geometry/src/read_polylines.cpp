#include "varsph/geometry/read_polylines.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "detail/input_checks.h"
#include "varsph/geometry/fill_polygons.h"
#include "varsph/geometry/geometry_error.h"

namespace varsph::geometry {
namespace {

// even-odd point in closed loop
bool point_in_loop(const Eigen::Vector2d& p, const Eigen::MatrixXd& P) {
  bool in = false;
  const Eigen::Index n = P.rows();
  for (Eigen::Index a = 0, b = n - 1; a < n; b = a++) {
    if ((P(a, 1) > p.y()) != (P(b, 1) > p.y()) &&
        p.x() < P(a, 0) + (p.y() - P(a, 1)) / (P(b, 1) - P(a, 1)) * (P(b, 0) - P(a, 0)))
      in = !in;
  }
  return in;
}

}  // namespace

int orient_loops(std::vector<Polyline2>& loops) {
  int reversed = 0;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    auto& L = loops[i];
    if (!L.closed || L.P.rows() < 3) continue;
    int depth = 0;
    const Eigen::Vector2d probe = L.P.row(0).transpose();
    for (std::size_t j = 0; j < loops.size(); ++j)
      if (j != i && loops[j].closed && loops[j].P.rows() >= 3 && point_in_loop(probe, loops[j].P)) ++depth;
    const bool want_ccw = depth % 2 == 0;
    if ((signed_area(L.P) > 0) != want_ccw) {
      L.P = L.P.colwise().reverse().eval();
      ++reversed;
    }
  }
  return reversed;
}

std::vector<Polyline2> read_polylines(const std::filesystem::path& path, const Eigen::Matrix4d& T,
                                      std::vector<std::string>& notes) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw GeometryError(path, "polyline file not found; expected an existing .poly2d file");
  std::ifstream in(path);
  if (!in) throw GeometryError(path, "polyline file cannot be opened for reading");
  std::vector<Polyline2> out;
  std::vector<Eigen::Vector2d> cur;
  std::vector<int> lines;  // file line of each point of `cur`
  bool open = false;
  int cur_line = 0;
  auto flush = [&]() {
    if (cur.empty()) { open = false; return; }
    if (cur.size() < 2 || (!open && cur.size() < 3))
      throw GeometryError(path, "line " + std::to_string(cur_line) + ": a loop needs at least 3 points (2 for an open polyline)");
    Polyline2 p;
    p.closed = !open;
    if (p.closed && (cur.front() - cur.back()).norm() == 0.0) cur.pop_back();  // repeated first point
    lines.resize(cur.size());
    p.P.resize(static_cast<Eigen::Index>(cur.size()), 2);
    for (std::size_t i = 0; i < cur.size(); ++i) {
      const Eigen::Vector4d q = T * Eigen::Vector4d(cur[i].x(), cur[i].y(), 0.0, 1.0);
      p.P.row(static_cast<Eigen::Index>(i)) << q.x(), q.y();
      if (!std::isfinite(q.x()) || !std::isfinite(q.y()) || std::abs(q.x()) > detail::kMaxCoordinate ||
          std::abs(q.y()) > detail::kMaxCoordinate)
        throw GeometryError(path, "line " + std::to_string(lines[i]) + ": point (" + std::to_string(cur[i].x()) + ", " +
                                      std::to_string(cur[i].y()) + ") is (" + std::to_string(q.x()) + ", " +
                                      std::to_string(q.y()) + ") m after the transform; expected finite coordinates "
                                      "within +-1e9 m");
    }
    out.push_back(std::move(p));
    cur.clear();
    lines.clear();
    open = false;
  };
  std::string line;
  int lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    const bool blank = line.find_first_not_of(" \t\r") == std::string::npos;
    if (auto h = line.find('#'); h != std::string::npos) line.resize(h);
    std::istringstream ss(line);
    std::string first;
    if (!(ss >> first)) {  // a blank line ends a loop; a comment-only line does not
      if (blank) flush();
      continue;
    }
    if (first == "open") { open = true; continue; }
    if (first == "closed") { open = false; continue; }
    std::istringstream ls(line);
    double x, y;
    std::string extra;
    if (!(ls >> x >> y) || (ls >> extra))
      throw GeometryError(path, "line " + std::to_string(lineno) + ": expected 'x y' (two numbers), 'open' or a comment, got '" + line + "'");
    if (!std::isfinite(x) || !std::isfinite(y))
      throw GeometryError(path, "line " + std::to_string(lineno) + ": expected finite coordinates, got '" + line + "'");
    cur.emplace_back(x, y);
    lines.push_back(lineno);
    cur_line = lineno;
  }
  flush();
  if (out.empty()) throw GeometryError(path, "polyline file holds no loop; expected lines 'x y'");
  if (const int r = orient_loops(out); r > 0)
    notes.push_back(path.string() + ": reversed " + std::to_string(r) + " loops (outer loops counter-clockwise, holes clockwise)");
  return out;
}

}  // namespace varsph::geometry
