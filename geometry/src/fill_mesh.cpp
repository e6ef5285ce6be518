#include "varsph/geometry/fill_mesh.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace varsph::geometry {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
}  // namespace

Eigen::MatrixXd fill_mesh(const TriangleMesh& tm, double dx, const Eigen::Vector3d& box_min,
                          const Eigen::Vector3d& box_max) {
  Mesh mesh;
  std::vector<Mesh::Vertex_index> vs;
  for (int i = 0; i < tm.V.rows(); ++i) vs.push_back(mesh.add_vertex(Point(tm.V(i, 0), tm.V(i, 1), tm.V(i, 2))));
  for (int f = 0; f < tm.F.rows(); ++f) mesh.add_face(vs[tm.F(f, 0)], vs[tm.F(f, 1)], vs[tm.F(f, 2)]);
  CGAL::Side_of_triangle_mesh<Mesh, K> inside(mesh);
  Eigen::Vector3i n;
  for (int a = 0; a < 3; ++a)
    n[a] = std::max(0, static_cast<int>(std::ceil((box_max[a] - box_min[a]) / dx - 0.5 - 1e-9)));  // centres below box_max
  // only the part of the box that overlaps the mesh bounding box can hold points
  const Eigen::Vector3d lo = tm.V.colwise().minCoeff().transpose(), hi = tm.V.colwise().maxCoeff().transpose();
  Eigen::Vector3i i0, i1;
  for (int a = 0; a < 3; ++a) {
    i0[a] = std::clamp(static_cast<int>(std::floor((lo[a] - box_min[a]) / dx - 0.5)), 0, n[a]);
    i1[a] = std::clamp(static_cast<int>(std::ceil((hi[a] - box_min[a]) / dx - 0.5)) + 1, 0, n[a]);
  }
  // Row by row: the x-line of the row is cut by the mesh at a few abscissae (AABB tree); between two
  // cuts the inside/outside answer is constant, so Side_of_triangle_mesh is asked once per interval
  // (and for every point closer than 1e-9 dx to a cut, or for rows lying in a face's plane).
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_face_graph_triangle_primitive<Mesh>>>;
  Tree tree(faces(mesh).first, faces(mesh).second, mesh);
  std::vector<Eigen::Vector3d> pts;
  std::vector<Mesh::Face_index> hits;
  std::vector<double> cuts;
  std::vector<signed char> state;
  for (int k = i0.z(); k < i1.z(); ++k)
    for (int j = i0.y(); j < i1.y(); ++j) {
      const double y = box_min.y() + (j + 0.5) * dx, z = box_min.z() + (k + 0.5) * dx;
      hits.clear();
      cuts.clear();
      tree.all_intersected_primitives(K::Line_3(Point(box_min.x(), y, z), K::Vector_3(1, 0, 0)), std::back_inserter(hits));
      bool per_point = false;
      for (auto f : hits) {
        auto h = mesh.halfedge(f);
        const Point& a = mesh.point(mesh.source(h));
        const K::Vector_3 n = CGAL::cross_product(mesh.point(mesh.target(h)) - a, mesh.point(mesh.target(mesh.next(h))) - a);
        if (std::abs(n.x()) <= 1e-12 * std::sqrt(n.squared_length())) { per_point = true; break; }
        // plane n . (p - a) = 0 along p = (x, y, z)
        cuts.push_back(a.x() - (n.y() * (y - a.y()) + n.z() * (z - a.z())) / n.x());
      }
      std::sort(cuts.begin(), cuts.end());
      state.assign(cuts.size() + 1, -1);
      for (int i = i0.x(); i < i1.x(); ++i) {
        const Eigen::Vector3d p = box_min + dx * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
        const Point q(p.x(), p.y(), p.z());
        bool in;
        const std::size_t slot = static_cast<std::size_t>(std::upper_bound(cuts.begin(), cuts.end(), p.x()) - cuts.begin());
        const bool near_cut = (slot > 0 && p.x() - cuts[slot - 1] < 1e-9 * dx) ||
                              (slot < cuts.size() && cuts[slot] - p.x() < 1e-9 * dx);
        if (per_point || near_cut) {
          in = inside(q) == CGAL::ON_BOUNDED_SIDE;
        } else {
          if (state[slot] < 0) state[slot] = inside(q) == CGAL::ON_BOUNDED_SIDE ? 1 : 0;
          in = state[slot] == 1;
        }
        if (in) pts.push_back(p);
      }
    }
  Eigen::MatrixXd X(static_cast<Eigen::Index>(pts.size()), 3);
  for (std::size_t i = 0; i < pts.size(); ++i) X.row(static_cast<Eigen::Index>(i)) = pts[i].transpose();
  return X;
}

Eigen::VectorXi points_inside_mesh(const TriangleMesh& tm, const Eigen::MatrixXd& points) {
  Mesh mesh;
  std::vector<Mesh::Vertex_index> vs;
  for (int i = 0; i < tm.V.rows(); ++i) vs.push_back(mesh.add_vertex(Point(tm.V(i, 0), tm.V(i, 1), tm.V(i, 2))));
  for (int f = 0; f < tm.F.rows(); ++f) mesh.add_face(vs[tm.F(f, 0)], vs[tm.F(f, 1)], vs[tm.F(f, 2)]);
  CGAL::Side_of_triangle_mesh<Mesh, K> inside(mesh);
  const Eigen::Vector3d lo = tm.V.colwise().minCoeff().transpose(), hi = tm.V.colwise().maxCoeff().transpose();
  Eigen::VectorXi flag = Eigen::VectorXi::Zero(points.rows());
  for (Eigen::Index k = 0; k < points.rows(); ++k) {
    const Eigen::Vector3d p = points.row(k).transpose();
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;  // outside the box: outside
    flag[k] = inside(Point(p.x(), p.y(), p.z())) == CGAL::ON_BOUNDED_SIDE ? 1 : 0;
  }
  return flag;
}

}  // namespace varsph::geometry
