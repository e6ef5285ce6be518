#include "varsph/geometry/slice_mesh.h"
#include <Eigen/Geometry>

#include <CGAL/AABB_halfedge_graph_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_slicer.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>

namespace varsph::geometry {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
}  // namespace

Eigen::Matrix<double, 2, 3> section_basis(const Eigen::Vector3d& normal) {
  const Eigen::Vector3d n = normal.normalized();
  Eigen::Matrix<double, 2, 3> B = Eigen::Matrix<double, 2, 3>::Zero();
  for (int a = 0; a < 3; ++a) {
    if (std::abs(std::abs(n[a]) - 1.0) < 1e-12) {  // coordinate axis: keep the two others in order
      int r = 0;
      for (int b = 0; b < 3; ++b)
        if (b != a) B(r++, b) = 1.0;
      return B;
    }
  }
  int least = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(n[a]) < std::abs(n[least])) least = a;
  const Eigen::Vector3d u = n.cross(Eigen::Vector3d::Unit(least)).normalized();
  B.row(0) = u.transpose();
  B.row(1) = n.cross(u).transpose();
  return B;
}

std::vector<Polyline2> slice_mesh(const TriangleMesh& tm, const Eigen::Vector3d& point,
                                  const Eigen::Vector3d& normal) {
  Mesh mesh;
  std::vector<Mesh::Vertex_index> vs;
  for (int i = 0; i < tm.V.rows(); ++i) vs.push_back(mesh.add_vertex(Point(tm.V(i, 0), tm.V(i, 1), tm.V(i, 2))));
  for (int f = 0; f < tm.F.rows(); ++f) mesh.add_face(vs[tm.F(f, 0)], vs[tm.F(f, 1)], vs[tm.F(f, 2)]);
  const Eigen::Vector3d n = normal.normalized();
  CGAL::Polygon_mesh_slicer<Mesh, K> slicer(mesh);
  std::vector<std::vector<Point>> lines;
  slicer(K::Plane_3(n.x(), n.y(), n.z(), -n.dot(point)), std::back_inserter(lines));
  const auto B = section_basis(n);
  std::vector<Polyline2> out;
  for (const auto& l : lines) {
    if (l.size() < 2) continue;
    Polyline2 p;
    std::size_t m = l.size();
    p.closed = l.size() > 2 && l.front() == l.back();
    if (p.closed) --m;
    p.P.resize(static_cast<Eigen::Index>(m), 2);
    for (std::size_t i = 0; i < m; ++i)
      p.P.row(static_cast<Eigen::Index>(i)) = (B * Eigen::Vector3d(l[i].x(), l[i].y(), l[i].z())).transpose();
    out.push_back(std::move(p));
  }
  orient_loops(out);
  return out;
}

}  // namespace varsph::geometry
