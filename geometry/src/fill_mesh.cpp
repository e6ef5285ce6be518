#include "varsph/geometry/fill_mesh.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

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
  std::vector<Eigen::Vector3d> pts;
  for (int k = i0.z(); k < i1.z(); ++k)
    for (int j = i0.y(); j < i1.y(); ++j)
      for (int i = i0.x(); i < i1.x(); ++i) {
        const Eigen::Vector3d p = box_min + dx * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
        if (inside(Point(p.x(), p.y(), p.z())) == CGAL::ON_BOUNDED_SIDE) pts.push_back(p);
      }
  Eigen::MatrixXd X(static_cast<Eigen::Index>(pts.size()), 3);
  for (std::size_t i = 0; i < pts.size(); ++i) X.row(static_cast<Eigen::Index>(i)) = pts[i].transpose();
  return X;
}

}  // namespace varsph::geometry
