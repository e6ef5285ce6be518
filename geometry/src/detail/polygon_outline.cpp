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
  double scale = 0;  // the largest |coordinate| and offset from corner 0: what the rounding scales with
  for (std::size_t i = 0; i < n; ++i) {
    const K::Vector_3 d = corners[i] - corners[0];
    s[i] = d.x() * ux + d.y() * uy + d.z() * uz;
    scale = std::max({scale, std::abs(d.x()) + std::abs(d.y()) + std::abs(d.z()),
                      std::abs(corners[i].x()) + std::abs(corners[i].y()) + std::abs(corners[i].z())});
  }
  const double un = std::abs(ux) + std::abs(uy) + std::abs(uz);
  const double pad = 1e-9 * scale * (un > 0 ? un : 1.0) + 1e-300;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto lo = [&](std::size_t e) { return std::min(s[e], s[(e + 1) % n]) - pad; };
  auto hi = [&](std::size_t e) { return std::max(s[e], s[(e + 1) % n]) + pad; };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return lo(a) < lo(b); });

  // in the projection: r on the closed segment [p, q], given that the three are collinear (CGAL's exact
  // lexicographic order along its projection axes orders collinear points along their line)
  const auto less_xy = CGAL::Projection_traits_3<K>(normal).less_xy_2_object();
  auto within = [&](const K::Point_3& p, const K::Point_3& q, const K::Point_3& r) {
    const bool pq = less_xy(p, q);
    const K::Point_3& lo_p = pq ? p : q;
    const K::Point_3& hi_p = pq ? q : p;
    return !less_xy(r, lo_p) && !less_xy(hi_p, r);
  };
  // two edges a, b that are not neighbours meet anywhere, crossing or touching
  auto meet = [&](std::size_t a, std::size_t b) {
    const auto &p = corners[a], &q = corners[(a + 1) % n], &r = corners[b], &t = corners[(b + 1) % n];
    const int o1 = int(orient(p, q, r)), o2 = int(orient(p, q, t));
    const int o3 = int(orient(r, t, p)), o4 = int(orient(r, t, q));
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    return (o1 == 0 && within(p, q, r)) || (o2 == 0 && within(p, q, t)) || (o3 == 0 && within(r, t, p)) ||
           (o4 == 0 && within(r, t, q));
  };
  // neighbours share corner b: they overlap beyond it when the outline turns back on itself at b
  for (std::size_t i = 0; i < n; ++i) {
    const auto &a = corners[i], &b = corners[(i + 1) % n], &c = corners[(i + 2) % n];
    if (!less_xy(a, b) && !less_xy(b, a)) return Outline::not_simple;  // an edge of no length in the projection
    if (orient(a, b, c) == CGAL::COLLINEAR && less_xy(b, a) == less_xy(b, c)) return Outline::not_simple;
  }
  std::vector<std::size_t> active;
  for (std::size_t e : order) {
    const double start = lo(e);
    active.erase(std::remove_if(active.begin(), active.end(), [&](std::size_t a) { return hi(a) < start; }),
                 active.end());
    for (std::size_t a : active) {
      const bool adjacent = (a + 1) % n == e || (e + 1) % n == a;  // checked above
      if (adjacent) continue;
      if (budget == 0) return Outline::over_budget;
      --budget;
      if (meet(a, e)) return Outline::not_simple;
    }
    active.push_back(e);
  }
  return Outline::simple;
}

}  // namespace varsph::geometry::detail
