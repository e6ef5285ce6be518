#include "varsph/geometry/sample_surface.h"
#include <Eigen/Geometry>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "detail/sample_selection.h"

namespace varsph::geometry {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Tri = K::Triangle_3;
using Prim = CGAL::AABB_triangle_primitive<K, std::vector<Tri>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Prim>>;
using detail::WeightedPoints;
using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr int kSub = 6;                 // sub-points per cell side for clipped cell areas
constexpr double kRegionMinCells = 16;  // planar regions smaller than this many dx^2 are "curved"
constexpr double kCandidatesPerDx = 4;  // candidate spacing dx/4 on curved parts, arcs and fans
constexpr double kMaxStretch = 0.1;     // a region lattice's spacing may differ from dx by 10 %

int find(std::vector<int>& p, int i) {
  while (p[i] != i) i = p[i] = p[p[i]];
  return i;
}

// Lattice of one planar region; returns false if the region is too irregular for a lattice.
bool region_lattice(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& faces,
                    const Vector3d& n, const Vector3d& u_dir, double area, double dx,
                    WeightedPoints& fixed, WeightedPoints& parcels) {
  const Vector3d u = (u_dir - u_dir.dot(n) * n).normalized(), v = n.cross(u);
  const Vector3d o = V.row(F(faces[0], 0)).transpose();
  double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
  for (int f : faces)
    for (int c = 0; c < 3; ++c) {
      const Vector3d p = V.row(F(f, c)).transpose() - o;
      umin = std::min(umin, p.dot(u)); umax = std::max(umax, p.dot(u));
      vmin = std::min(vmin, p.dot(v)); vmax = std::max(vmax, p.dot(v));
    }
  // round(extent / dx) cells per axis exactly tile the bounding box: the spacing is dx when the
  // extent is a multiple of dx, else stretched by at most dx / (2 n) (particles then sit half a
  // cell from the bounding-box edges, which keeps neighbouring regions at >= 0.7 spacing)
  const int nu = std::max(1, static_cast<int>(std::lround((umax - umin) / dx)));
  const int nv = std::max(1, static_cast<int>(std::lround((vmax - vmin) / dx)));
  const double hu = (umax - umin) / nu, hv = (vmax - vmin) / nv;
  if (std::abs(hu / dx - 1.0) > kMaxStretch || std::abs(hv / dx - 1.0) > kMaxStretch) return false;
  const double ou = umin, ov = vmin;
  const int cu = nu + 2, cv = nv + 2;  // cells -1 .. n (guards for round-off at the ends)
  if (static_cast<double>(cu) * cv > 4e8) return false;
  struct Cell { int count = 0; bool centre_in = false; double best_d = INFINITY; Vector2d best{0, 0}; };
  std::vector<Cell> cells(static_cast<std::size_t>(cu) * cv);
  double su[kSub], sv[kSub];
  for (int a = 0; a < kSub; ++a) { su[a] = (a + 0.5) / kSub; sv[a] = (a + 0.55) / kSub; }
  for (int f : faces) {
    Vector2d t[3];
    for (int c = 0; c < 3; ++c) {
      const Vector3d p = V.row(F(f, c)).transpose() - o;
      t[c] = Vector2d(p.dot(u) - ou, p.dot(v) - ov);  // lattice coordinates [m]
    }
    // edge functions of the counter-clockwise triangle (inclusive)
    auto inside = [&](const Vector2d& p) {
      for (int c = 0; c < 3; ++c) {
        const Vector2d& a = t[c];
        const Vector2d& b = t[(c + 1) % 3];
        if ((b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x()) < 0) return false;
      }
      return true;
    };
    const double lo_u = std::min({t[0].x(), t[1].x(), t[2].x()}), hi_u = std::max({t[0].x(), t[1].x(), t[2].x()});
    const double lo_v = std::min({t[0].y(), t[1].y(), t[2].y()}), hi_v = std::max({t[0].y(), t[1].y(), t[2].y()});
    const int i0 = std::max(-1, static_cast<int>(std::floor(lo_u / hu))), i1 = std::min(nu, static_cast<int>(std::floor(hi_u / hu)));
    const int j0 = std::max(-1, static_cast<int>(std::floor(lo_v / hv))), j1 = std::min(nv, static_cast<int>(std::floor(hi_v / hv)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        Cell& cell = cells[static_cast<std::size_t>(j + 1) * cu + (i + 1)];
        const Vector2d c0(i * hu, j * hv), centre = c0 + Vector2d(0.5 * hu, 0.5 * hv);
        if (inside(centre)) { cell.centre_in = true; cell.best_d = 0; cell.best = centre; }
        if (inside(c0) && inside(c0 + Vector2d(hu, 0)) && inside(c0 + Vector2d(0, hv)) && inside(c0 + Vector2d(hu, hv))) {
          cell.count += kSub * kSub;
          continue;
        }
        for (int b = 0; b < kSub; ++b)
          for (int a = 0; a < kSub; ++a) {
            const Vector2d p = c0 + Vector2d(hu * su[a], hv * sv[b]);
            if (!inside(p)) continue;
            ++cell.count;
            const double d = (p - centre).squaredNorm();
            if (d < cell.best_d) { cell.best_d = d; cell.best = p; }
          }
      }
  }
  double sampled = 0;
  for (const auto& c : cells) sampled += std::min(c.count, kSub * kSub);
  if (sampled <= 0) return false;
  const double scale = area / sampled;  // every sub-point stands for this much area
  double kept = 0;
  WeightedPoints f_out, p_out;
  for (int j = -1; j <= nv; ++j)
    for (int i = -1; i <= nu; ++i) {
      const Cell& c = cells[static_cast<std::size_t>(j + 1) * cu + (i + 1)];
      if (c.count == 0) continue;
      const int cnt = std::min(c.count, kSub * kSub);
      const Vector3d x = o + (c.best.x() + ou) * u + (c.best.y() + ov) * v;
      if (2 * cnt >= kSub * kSub) {
        f_out.add(x, n, cnt * scale);
        kept += cnt * scale;
      } else {
        p_out.add(x, n, cnt * scale);
      }
    }
  if (kept < 0.9 * area) return false;
  for (std::size_t i = 0; i < f_out.size(); ++i) fixed.add(f_out.x[i], f_out.n[i], f_out.w[i]);
  for (std::size_t i = 0; i < p_out.size(); ++i) parcels.add(p_out.x[i], p_out.n[i], p_out.w[i]);
  return true;
}

// Centroids of the m*m sub-triangles of the barycentric grid of (a, b, c), as weights (wa, wb, wc).
template <class F>
void barycentric_grid(int m, F&& f) {
  for (int i = 0; i < m; ++i)
    for (int j = 0; i + j < m; ++j) {
      f((i + 1.0 / 3) / m, (j + 1.0 / 3) / m);
      if (i + j < m - 1) f((i + 2.0 / 3) / m, (j + 2.0 / 3) / m);
    }
}

// Points of the square lattice of spacing h in the plane of (a, b, c), axis along the longest edge,
// clipped to the triangle (the centroid if none falls inside): about area/h^2 points for any shape.
template <class F>
void triangle_lattice(const Vector3d& a, const Vector3d& b, const Vector3d& c, double h, F&& f) {
  const Vector3d P[3] = {a, b, c};
  int e = 0;
  double best = -1;
  for (int i = 0; i < 3; ++i) {
    const double l = (P[(i + 1) % 3] - P[i]).squaredNorm();
    if (l > best) { best = l; e = i; }
  }
  const Vector3d o = P[e], u = (P[(e + 1) % 3] - o).normalized();
  const Vector3d n = (b - a).cross(c - a).normalized();
  const Vector3d v = n.cross(u);
  const Vector2d q[3] = {{0, 0}, {(P[(e + 1) % 3] - o).dot(u), 0}, {(P[(e + 2) % 3] - o).dot(u), (P[(e + 2) % 3] - o).dot(v)}};
  // q is counter-clockwise (v points towards the third vertex)
  const double umax = q[1].x(), vmax = q[2].y();
  const double umin = std::min(0.0, q[2].x()), umax2 = std::max(umax, q[2].x());
  int count = 0;
  for (int j = 0; (j + 0.5) * h < vmax; ++j)
    for (int i = static_cast<int>(std::floor(umin / h)); (i + 0.5) * h < umax2; ++i) {
      const Vector2d p((i + 0.5) * h, (j + 0.5) * h);
      bool in = true;
      for (int k = 0; k < 3 && in; ++k) {
        const Vector2d& s0 = q[k];
        const Vector2d& s1 = q[(k + 1) % 3];
        in = (s1.x() - s0.x()) * (p.y() - s0.y()) - (s1.y() - s0.y()) * (p.x() - s0.x()) >= 0;
      }
      if (!in) continue;
      f(Vector3d(o + p.x() * u + p.y() * v), 0);
      ++count;
    }
  if (count == 0) f(Vector3d((a + b + c) / 3.0), 0);
  f(Vector3d::Zero(), count == 0 ? 1 : count);  // end marker with the number of points
}

}  // namespace

void sample_surface(const TriangleMesh& mesh, double dx, int layers, int side, Eigen::MatrixXd& X,
                    Eigen::MatrixXd& N, Eigen::VectorXd& A, Eigen::VectorXi& L) {
  const Eigen::MatrixXd& V = mesh.V;
  const Eigen::MatrixXi& F = mesh.F;
  const int nf = static_cast<int>(F.rows()), nvert = static_cast<int>(V.rows());
  const double s = side >= 0 ? 1.0 : -1.0;
  const double h = dx / kCandidatesPerDx;
  std::vector<Vector3d> fn(nf);
  std::vector<double> fa(nf);
  for (int f = 0; f < nf; ++f) {
    const Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Vector3d cr = (b - a).cross(c - a);
    fa[f] = 0.5 * cr.norm();
    fn[f] = fa[f] > 0 ? Vector3d(cr.normalized()) : Vector3d::UnitZ();
  }
  // edges -> adjacent faces
  struct Edge { int a, b; int f[2] = {-1, -1}; int count = 0; };
  std::vector<Edge> edges;
  {
    std::unordered_map<std::uint64_t, int> index;
    index.reserve(static_cast<std::size_t>(nf) * 2);
    for (int f = 0; f < nf; ++f)
      for (int c = 0; c < 3; ++c) {
        int a = F(f, c), b = F(f, (c + 1) % 3);
        if (a > b) std::swap(a, b);
        const std::uint64_t key = static_cast<std::uint64_t>(a) * static_cast<std::uint64_t>(nvert) + b;
        auto [it, fresh] = index.try_emplace(key, static_cast<int>(edges.size()));
        if (fresh) edges.push_back(Edge{a, b});
        Edge& e = edges[it->second];
        if (e.count < 2) e.f[e.count] = f;
        ++e.count;
      }
  }
  // planar regions: union of faces across edges with parallel normals
  std::vector<int> parent(nf);
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& e : edges)
    if (e.count == 2 && fn[e.f[0]].dot(fn[e.f[1]]) > 1.0 - 1e-10) parent[find(parent, e.f[0])] = find(parent, e.f[1]);
  std::vector<std::vector<int>> region_faces(nf);
  for (int f = 0; f < nf; ++f) region_faces[find(parent, f)].push_back(f);
  // longest region-boundary edge of each region gives its lattice axis
  std::vector<Vector3d> region_axis(nf, Vector3d::Zero());
  std::vector<double> region_axis_len(nf, -1);
  for (const auto& e : edges) {
    const bool boundary = e.count != 2 || find(parent, e.f[0]) != find(parent, e.f[1]);
    if (!boundary) continue;
    const double len = (V.row(e.b) - V.row(e.a)).norm();
    for (int k = 0; k < std::min(e.count, 2); ++k) {
      const int r = find(parent, e.f[k]);
      if (len > region_axis_len[r]) { region_axis_len[r] = len; region_axis[r] = (V.row(e.b) - V.row(e.a)).transpose(); }
    }
  }
  WeightedPoints fixed0, parcels0;
  std::vector<int> curved;
  for (int r = 0; r < nf; ++r) {
    if (region_faces[r].empty()) continue;
    double area = 0;
    for (int f : region_faces[r]) area += fa[f];
    if (area <= 0) continue;
    const bool lattice = area >= kRegionMinCells * dx * dx && region_axis_len[r] > 0 &&
                         region_lattice(V, F, region_faces[r], fn[r], region_axis[r], area, dx, fixed0, parcels0);
    if (!lattice)
      for (int f : region_faces[r]) curved.push_back(f);
  }
  std::sort(curved.begin(), curved.end());
  // area-weighted vertex normals (on the layer side) for the corner fans
  std::vector<Vector3d> vn(nvert, Vector3d::Zero());
  for (int f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) vn[F(f, c)] += fa[f] * fn[f];
  for (auto& n : vn) n = n.norm() > 0 ? Vector3d(s * n.normalized()) : Vector3d::Zero();

  std::vector<Tri> tris;
  Tree tree;
  if (layers > 1) {
    tris.reserve(nf);
    for (int f = 0; f < nf; ++f) {
      const Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      tris.emplace_back(K::Point_3(a.x(), a.y(), a.z()), K::Point_3(b.x(), b.y(), b.z()), K::Point_3(c.x(), c.y(), c.z()));
    }
    tree.insert(tris.begin(), tris.end());
    tree.build();
    tree.accelerate_distance_queries();
  }

  std::vector<Vector3d> xs, ns;
  std::vector<double> as;
  std::vector<int> ls;
  for (int k = 0; k < layers; ++k) {
    const double off = k * dx;
    auto keep = [&](const Vector3d& p) {
      if (k == 0) return true;
      const double d = std::sqrt(CGAL::to_double(tree.squared_distance(K::Point_3(p.x(), p.y(), p.z()))));
      return std::abs(d - off) <= 1e-3 * dx;
    };
    WeightedPoints fixed, cand, parcels;
    for (std::size_t i = 0; i < fixed0.size(); ++i) {
      const Vector3d p = fixed0.x[i] + s * off * fixed0.n[i];
      if (keep(p)) fixed.add(p, fixed0.n[i], fixed0.w[i]);
    }
    for (std::size_t i = 0; i < parcels0.size(); ++i) {
      const Vector3d p = parcels0.x[i] + s * off * parcels0.n[i];
      if (keep(p)) parcels.add(p, parcels0.n[i], parcels0.w[i]);
    }
    for (int f : curved) {
      const Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      const Vector3d push = s * off * fn[f];
      std::vector<Vector3d> pts;
      triangle_lattice(a, b, c, h, [&](const Vector3d& p, int count) {
        if (count == 0) { pts.push_back(p); return; }
        const double w = fa[f] / count;
        for (const auto& q : pts)
          if (keep(q + push)) cand.add(q + push, fn[f], w);
      });
    }
    if (k > 0) {
      for (const auto& e : edges) {
        if (e.count != 2) continue;
        const Vector3d n1 = s * fn[e.f[0]], n2 = s * fn[e.f[1]];
        const double theta = std::acos(std::clamp(n1.dot(n2), -1.0, 1.0));
        if (theta < 1e-3 || theta > M_PI - 1e-3) continue;
        // cylinder piece swept by the edge: slerp between the two face normals
        const Vector3d pa = V.row(e.a), pb = V.row(e.b);
        const double len = (pb - pa).norm();
        const int me = std::max(1, static_cast<int>(std::ceil(len / h)));
        const int ma = std::max(1, static_cast<int>(std::ceil(off * theta / h)));
        const double w = len * off * theta / (static_cast<double>(me) * ma);
        for (int ia = 0; ia < ma; ++ia) {
          const double t = (ia + 0.5) / ma;
          const Vector3d dir = (std::sin((1 - t) * theta) * n1 + std::sin(t * theta) * n2) / std::sin(theta);
          for (int ie = 0; ie < me; ++ie) {
            const Vector3d p = pa + (ie + 0.5) / me * (pb - pa) + off * dir;
            if (keep(p)) cand.add(p, s * dir, w);
          }
        }
        // sphere pieces at both vertices: fan triangle (vertex normal, n1, n2)
        for (int vtx : {e.a, e.b}) {
          const Vector3d n0 = vn[vtx];
          if (n0.squaredNorm() == 0) continue;
          // solid angle of the spherical triangle (Van Oosterom & Strackee 1983)
          const double omega = 2.0 * std::atan2(std::abs(n0.dot(n1.cross(n2))), 1.0 + n0.dot(n1) + n1.dot(n2) + n2.dot(n0));
          if (omega <= 1e-9) continue;
          const double span = std::max({std::acos(std::clamp(n0.dot(n1), -1.0, 1.0)), theta,
                                        std::acos(std::clamp(n0.dot(n2), -1.0, 1.0))});
          const int m = std::max(1, static_cast<int>(std::ceil(off * span / h)));
          const double w = off * off * omega / (static_cast<double>(m) * m);
          const Vector3d pv = V.row(vtx);
          barycentric_grid(m, [&](double wb, double wc) {
            const Vector3d dir = ((1 - wb - wc) * n0 + wb * n1 + wc * n2).normalized();
            const Vector3d p = pv + off * dir;
            if (keep(p)) cand.add(p, s * dir, w);
          });
        }
      }
    }
    const detail::Layer layer = detail::select_samples(fixed, cand, parcels, dx, 2, 0.55 * dx, true);
    for (std::size_t i = 0; i < layer.x.size(); ++i) {
      xs.push_back(layer.x[i]); ns.push_back(layer.n[i]); as.push_back(layer.a[i]); ls.push_back(k);
    }
  }
  const Eigen::Index n = static_cast<Eigen::Index>(xs.size());
  X.resize(n, 3); N.resize(n, 3); A.resize(n); L.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    X.row(i) = xs[i].transpose(); N.row(i) = ns[i].transpose(); A[i] = as[i]; L[i] = ls[i];
  }
}

}  // namespace varsph::geometry
