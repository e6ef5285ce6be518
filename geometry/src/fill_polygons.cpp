#include "varsph/geometry/fill_polygons.h"

#include <algorithm>
#include <cmath>

namespace varsph::geometry {

double signed_area(const Eigen::MatrixXd& P) {
  double a = 0;
  const Eigen::Index n = P.rows();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index j = (i + 1) % n;
    a += P(i, 0) * P(j, 1) - P(j, 0) * P(i, 1);  // shoelace formula
  }
  return 0.5 * a;
}

Eigen::MatrixXd fill_polygons(const std::vector<Polyline2>& loops, double dx,
                              const Eigen::Vector2d& box_min, const Eigen::Vector2d& box_max) {
  const int nx = std::max(0, static_cast<int>(std::ceil((box_max.x() - box_min.x()) / dx - 0.5 - 1e-9)));
  const int ny = std::max(0, static_cast<int>(std::ceil((box_max.y() - box_min.y()) / dx - 0.5 - 1e-9)));
  std::vector<Eigen::Vector2d> pts;
  std::vector<double> xs;
  for (int j = 0; j < ny; ++j) {
    const double y = box_min.y() + (j + 0.5) * dx;
    // crossings of the horizontal line y with every loop edge (half-open rule: even-odd)
    xs.clear();
    for (const auto& L : loops) {
      if (!L.closed) continue;
      const Eigen::Index n = L.P.rows();
      for (Eigen::Index a = 0; a < n; ++a) {
        const Eigen::Index b = (a + 1) % n;
        const double ya = L.P(a, 1), yb = L.P(b, 1);
        if ((ya <= y) == (yb <= y)) continue;
        xs.push_back(L.P(a, 0) + (y - ya) / (yb - ya) * (L.P(b, 0) - L.P(a, 0)));
      }
    }
    std::sort(xs.begin(), xs.end());
    for (std::size_t c = 0; c + 1 < xs.size(); c += 2) {
      // lattice columns strictly inside (xs[c], xs[c+1])
      const int i0 = std::max(0, static_cast<int>(std::floor((xs[c] - box_min.x()) / dx - 0.5)));
      const int i1 = std::min(nx - 1, static_cast<int>(std::ceil((xs[c + 1] - box_min.x()) / dx - 0.5)));
      for (int i = i0; i <= i1; ++i) {
        const double x = box_min.x() + (i + 0.5) * dx;
        if (x > xs[c] && x < xs[c + 1]) pts.emplace_back(x, y);
      }
    }
  }
  Eigen::MatrixXd X(static_cast<Eigen::Index>(pts.size()), 2);
  for (std::size_t i = 0; i < pts.size(); ++i) X.row(static_cast<Eigen::Index>(i)) = pts[i].transpose();
  return X;
}

}  // namespace varsph::geometry
