#include "polygon_outline.h"

#include <CGAL/Projection_traits_3.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace varsph::geometry::detail {

Outline check_outline(const std::vector<OutlineKernel::Point_3>& corners, const OutlineKernel::Vector_3& normal,
                      std::size_t& budget) {
  using K = OutlineKernel;
  const std::size_t n = corners.size();
  if (n < 4) return Outline::simple;  // a triangle's edges are all adjacent
  // the predicate CGAL's projected triangulation uses: sign of det(q - p, r - p, normal), exact
  const auto orient = CGAL::Projection_traits_3<K>(normal).orientation_2_object();

  // broad phase: sort and sweep the edges' extents along one direction u in the projection plane. The
  // extents are rounded doubles, so each is widened by far more than their rounding; the exact test
  // below decides.
  const double nx = normal.x(), ny = normal.y(), nz = normal.z();
  double ux = 0, uy = 0, uz = 0;  // u = normal x (the axis least aligned with it)
  if (std::abs(nx) <= std::abs(ny) && std::abs(nx) <= std::abs(nz)) uy = nz, uz = -ny;
  else if (std::abs(ny) <= std::abs(nz)) ux = -nz, uz = nx;
  else ux = ny, uy = -nx;
  std::vector<double> s(n);
  double scale = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const K::Vector_3 d = corners[i] - corners[0];
    s[i] = d.x() * ux + d.y() * uy + d.z() * uz;
    scale = std::max(scale, std::abs(d.x()) + std::abs(d.y()) + std::abs(d.z()));
  }
  const double un = std::abs(ux) + std::abs(uy) + std::abs(uz);
  const double pad = 1e-9 * scale * (un > 0 ? un : 1.0) + 1e-300;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto lo = [&](std::size_t e) { return std::min(s[e], s[(e + 1) % n]) - pad; };
  auto hi = [&](std::size_t e) { return std::max(s[e], s[(e + 1) % n]) + pad; };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return lo(a) < lo(b); });

  auto cross = [&](std::size_t a, std::size_t b) {  // edges a and b properly cross
    const auto &p = corners[a], &q = corners[(a + 1) % n], &r = corners[b], &t = corners[(b + 1) % n];
    const int o1 = int(orient(p, q, r)), o2 = int(orient(p, q, t));
    if (o1 * o2 >= 0) return false;
    return int(orient(r, t, p)) * int(orient(r, t, q)) < 0;
  };
  std::vector<std::size_t> active;
  for (std::size_t e : order) {
    const double start = lo(e);
    active.erase(std::remove_if(active.begin(), active.end(), [&](std::size_t a) { return hi(a) < start; }),
                 active.end());
    for (std::size_t a : active) {
      const bool adjacent = (a + 1) % n == e || (e + 1) % n == a;  // share a corner: CDT needs no construction
      if (adjacent) continue;
      if (budget == 0) return Outline::over_budget;
      --budget;
      if (cross(a, e)) return Outline::crosses;
    }
    active.push_back(e);
  }
  return Outline::simple;
}

}  // namespace varsph::geometry::detail
