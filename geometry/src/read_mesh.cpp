#include "varsph/geometry/read_mesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "detail/input_checks.h"
#include "detail/polygon_outline.h"
#include "varsph/geometry/geometry_error.h"

namespace varsph::geometry {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

std::string lower_ext(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}
// Vertices sorted lexicographically, each face rotated to start at its smallest vertex (orientation
// kept), faces sorted: the result no longer depends on the order the file listed them in, so every
// file format of the same mesh gives the same particles.
void canonical_order(Eigen::MatrixXd& V, Eigen::MatrixXi& F) {
  const int nv = static_cast<int>(V.rows()), nf = static_cast<int>(F.rows());
  std::vector<int> order(nv);
  for (int i = 0; i < nv; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    for (int k = 0; k < 3; ++k)
      if (V(a, k) != V(b, k)) return V(a, k) < V(b, k);
    return a < b;
  });
  std::vector<int> inv(nv);
  Eigen::MatrixXd V2(nv, 3);
  for (int i = 0; i < nv; ++i) { V2.row(i) = V.row(order[i]); inv[order[i]] = i; }
  std::vector<std::array<int, 3>> faces(nf);
  for (int f = 0; f < nf; ++f) {
    std::array<int, 3> t{inv[F(f, 0)], inv[F(f, 1)], inv[F(f, 2)]};
    while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
    faces[f] = t;
  }
  std::sort(faces.begin(), faces.end());
  for (int f = 0; f < nf; ++f) F.row(f) << faces[f][0], faces[f][1], faces[f][2];
  V = V2;
}

}  // namespace

TriangleMesh read_mesh(const std::filesystem::path& path, const Eigen::Matrix4d& T,
                       bool check_self_intersection, std::vector<std::string>& notes,
                       const std::function<void(double)>& check_soup_area) {
  const std::string ext = lower_ext(path);
  if (ext != ".stl" && ext != ".obj" && ext != ".off" && ext != ".ply")
    throw GeometryError(path, "unsupported mesh file extension '" + path.extension().string() +
                                  "'; expected .stl, .obj, .off or .ply");
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw GeometryError(path, "mesh file not found; expected an existing .stl/.obj/.off/.ply file");
  if (std::filesystem::is_directory(path, ec))
    throw GeometryError(path, "is a directory; expected a mesh file");
  {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw GeometryError(path, "mesh file cannot be opened for reading");
  }
  if (std::filesystem::file_size(path, ec) == 0)
    throw GeometryError(path, "mesh file is empty; expected at least one triangle");

  // counts the header declares must fit the file before a reader allocates from them
  detail::check_declared_counts(path, ext);
  if (check_soup_area && ext == ".stl") {  // binary STL: the estimate straight from the file, before CGAL
    const double A[9] = {T(0, 0), T(0, 1), T(0, 2), T(1, 0), T(1, 1), T(1, 2), T(2, 0), T(2, 1), T(2, 2)};
    if (const double area = detail::binary_stl_area(path, A); area >= 0 && std::isfinite(area)) check_soup_area(area);
  }

  std::vector<Point> pts;
  std::vector<std::vector<std::size_t>> polys;
  bool ok = false;
  try {
    ok = CGAL::IO::read_polygon_soup(path.string(), pts, polys, CGAL::parameters::verbose(false));
  } catch (const std::exception& e) {
    throw GeometryError(path, std::string("cannot parse mesh file (") + e.what() + ")");
  }
  // a reader that stopped early (premature end, bad token) may leave a partial soup: never use it
  if (!ok)
    throw GeometryError(path, "cannot parse mesh file as " + ext.substr(1) +
                                  "; expected a valid polygon mesh in that format (truncated or damaged?)");
  if (polys.empty()) throw GeometryError(path, "mesh file holds no faces; expected at least one triangle");

  // non-finite or absurd coordinates stop here, before any repair or sampler sees them
  auto check = [&](bool bounded, const char* stage) {
    std::vector<double> xyz(3 * pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      xyz[3 * i] = pts[i].x(); xyz[3 * i + 1] = pts[i].y(); xyz[3 * i + 2] = pts[i].z();
    }
    detail::check_coordinates(path, xyz.data(), pts.size(), bounded, stage);
  };
  check(false, "in the file");
  // transform the vertices first (repairs then work in metres)
  for (auto& p : pts) {
    const Eigen::Vector4d q = T * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
    p = Point(q.x(), q.y(), q.z());
  }
  check(true, "after the transform");
  if (check_soup_area) {  // the raw soup's area (polygons fanned into triangles), before the repairs
    double area = 0;
    for (const auto& poly : polys)
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
        if (poly[0] >= pts.size() || poly[k] >= pts.size() || poly[k + 1] >= pts.size()) continue;
        area += std::sqrt(CGAL::squared_area(pts[poly[0]], pts[poly[k]], pts[poly[k + 1]]));
      }
    check_soup_area(area);
  }
  // merge exactly duplicated vertices
  std::map<Point, std::size_t> unique;
  std::vector<Point> upts;
  std::vector<std::size_t> remap(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    auto [it, fresh] = unique.try_emplace(pts[i], upts.size());
    if (fresh) upts.push_back(pts[i]);
    remap[i] = it->second;
  }
  const std::size_t merged = pts.size() - upts.size();
  if (merged > 0 && ext != ".stl")  // STL stores each triangle's corners separately: merging is normal
    notes.push_back(path.string() + ": merged " + std::to_string(merged) + " duplicated vertices");
  // drop faces that repeat a vertex (zero area) and exact duplicate faces
  std::size_t degenerate = 0, duplicate = 0;
  std::vector<std::vector<std::size_t>> fpolys;
  std::map<std::vector<std::size_t>, int> seen;
  for (auto& poly : polys) {
    std::vector<std::size_t> q;
    for (auto v : poly) {
      if (v >= remap.size()) throw GeometryError(path, "face refers to a missing vertex");
      q.push_back(remap[v]);
    }
    std::vector<std::size_t> s = q;
    std::sort(s.begin(), s.end());
    if (q.size() < 3 || std::adjacent_find(s.begin(), s.end()) != s.end()) { ++degenerate; continue; }
    if (!seen.emplace(s, 1).second) { ++duplicate; continue; }
    fpolys.push_back(std::move(q));
  }
  if (fpolys.empty()) throw GeometryError(path, "mesh has no non-degenerate face");
  if (duplicate > 0)
    notes.push_back(path.string() + ": removed " + std::to_string(duplicate) + " duplicated faces");
  // vertices no face uses: CGAL's mesh repairs require a valid polygon mesh, where every vertex has an edge
  if (const std::size_t unused = PMP::remove_isolated_points_in_polygon_soup(upts, fpolys); unused > 0)
    notes.push_back(path.string() + ": ignored " + std::to_string(unused) + " vertices that no face uses");
  const auto before = fpolys;
  if (!PMP::orient_polygon_soup(upts, fpolys))
    notes.push_back(path.string() + ": non-manifold vertices were duplicated to orient the faces");
  std::size_t flipped = 0;
  for (std::size_t i = 0; i < std::min(before.size(), fpolys.size()); ++i)
    if (before[i] != fpolys[i]) ++flipped;
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(upts, fpolys, mesh);
  // what CGAL's repairs and triangulation take as a precondition (checked only in its debug builds)
  if (!CGAL::is_valid_polygon_mesh(mesh))
    throw GeometryError(path, "its faces do not form a valid surface after orientation (faces folded onto each "
                              "other?); expected a surface of triangles or simple polygons");
  // a polygon outline that is not simple is refused before CGAL's triangulation sees it (where it could
  // loop without end or break the mesh: detail/polygon_outline.h)
  std::size_t pair_budget = detail::kOutlinePairBudget;
  for (auto f : mesh.faces()) {
    if (mesh.degree(f) <= 4) continue;  // CGAL splits quads along a diagonal, without a triangulation
    const K::Vector_3 normal = PMP::compute_face_normal(f, mesh);  // what CGAL projects along
    if (normal == K::Vector_3(0, 0, 0)) continue;                  // CGAL refuses it: the message below
    std::vector<Point> corners;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) corners.push_back(mesh.point(v));
    const auto outline = detail::check_outline(corners, normal, pair_budget);
    if (outline == detail::Outline::simple) continue;
    std::ostringstream where;
    where << "a polygon face of " << corners.size() << " corners (the first at " << corners[0] << ")";
    if (outline == detail::Outline::not_simple)
      throw GeometryError(path, where.str() + " is not a simple polygon seen along its normal (edges that cross "
                                              "or touch, or an outline turning back on itself); expected "
                                              "triangles or simple planar polygons");
    throw GeometryError(path, "the polygon faces' edges overlap in more than " +
                                  std::to_string(detail::kOutlinePairBudget) + " pairs (at " + where.str() +
                                  "); expected triangles or simple planar polygons");
  }
  // a polygon CGAL cannot split (degenerate or non-simple) stays a polygon: refused, since everything
  // below reads three corners per face (a fuzzed 6-corner OBJ face overflowed out.F before this check)
  if (!CGAL::is_triangle_mesh(mesh) && (!PMP::triangulate_faces(mesh) || !CGAL::is_triangle_mesh(mesh)))
    throw GeometryError(path, "a polygon face cannot be split into triangles (degenerate or self-intersecting "
                              "polygon?); expected triangles or simple planar polygons");
  if (!CGAL::is_valid_polygon_mesh(mesh))  // the precondition of the repair below
    throw GeometryError(path, "splitting its polygon faces into triangles did not give a valid surface; expected "
                              "triangles or simple planar polygons");
  {
    const std::size_t nf = mesh.number_of_faces();
    PMP::remove_degenerate_faces(mesh);
    mesh.collect_garbage();
    degenerate += nf - mesh.number_of_faces();
  }
  // CGAL's repair assumes a valid triangle mesh and can leave a polygon behind when the soup was not one
  // (a fuzzed OBJ: a 4-corner face after it overflowed out.F below)
  if (!CGAL::is_valid_polygon_mesh(mesh) || !CGAL::is_triangle_mesh(mesh))
    throw GeometryError(path, "removing its degenerate faces left a face that is not a triangle (faces folded onto "
                              "each other?); expected a surface of non-degenerate triangles or simple polygons");
  if (degenerate > 0)
    notes.push_back(path.string() + ": removed " + std::to_string(degenerate) + " degenerate faces");
  if (mesh.number_of_faces() == 0) throw GeometryError(path, "mesh has no non-degenerate face");

  TriangleMesh out;
  for (auto h : mesh.halfedges())
    if (mesh.is_border(h)) ++out.border_edges;
  if (out.border_edges == 0) {
    auto cc = mesh.add_property_map<Mesh::Face_index, std::size_t>("f:varsph_cc", 0).first;
    const std::size_t ncc = PMP::connected_components(mesh, cc);
    if (ncc <= 1) {
      if (!PMP::is_outward_oriented(mesh)) {
        PMP::reverse_face_orientations(mesh);
        flipped = mesh.number_of_faces() - flipped;
      }
    } else {
      // several closed components (e.g. a tank and an obstacle in one file): each one is turned to
      // enclose a positive volume (nested shells are therefore not treated as a hollow solid)
      std::vector<double> vol(ncc, 0.0);
      for (auto f : mesh.faces()) {
        auto h = mesh.halfedge(f);
        const auto& p = mesh.point(mesh.source(h));
        const auto& q = mesh.point(mesh.target(h));
        const auto& r = mesh.point(mesh.target(mesh.next(h)));
        vol[cc[f]] += CGAL::scalar_product(p - CGAL::ORIGIN, CGAL::cross_product(q - CGAL::ORIGIN, r - CGAL::ORIGIN)) / 6.0;
      }
      std::vector<Mesh::Face_index> rev;
      for (auto f : mesh.faces())
        if (vol[cc[f]] < 0) rev.push_back(f);
      if (!rev.empty()) {
        PMP::reverse_face_orientations(rev, mesh);
        notes.push_back(path.string() + ": reversed the orientation of " + std::to_string(rev.size()) +
                        " faces so that each of the " + std::to_string(ncc) + " closed components faces outward");
      }
    }
    mesh.remove_property_map(cc);
    out.volume = PMP::volume(mesh);
  }
  if (flipped > 0)
    notes.push_back(path.string() + ": reversed the orientation of " + std::to_string(flipped) +
                    " faces (consistent" + (out.border_edges == 0 ? ", outward)" : ")"));
  out.area = PMP::area(mesh);
  if (check_self_intersection) out.self_intersecting = PMP::does_self_intersect(mesh);

  out.V.resize(mesh.number_of_vertices(), 3);
  std::map<Mesh::Vertex_index, int> vid;
  int i = 0;
  for (auto v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    out.V.row(i) << p.x(), p.y(), p.z();
    vid[v] = i++;
  }
  out.F.resize(mesh.number_of_faces(), 3);
  i = 0;
  for (auto f : mesh.faces()) {
    int c = 0;
    for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (c == 3) throw GeometryError(path, "a face has more than three corners after the repairs; expected triangles");
      out.F(i, c++) = vid[v];
    }
    ++i;
  }
  canonical_order(out.V, out.F);
  return out;
}

}  // namespace varsph::geometry
