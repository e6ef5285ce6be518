#include "varsph/geometry/sample_body.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "varsph/geometry/fill_mesh.h"
#include "varsph/geometry/fill_polygons.h"
#include "varsph/geometry/geometry_error.h"
#include "varsph/geometry/points_far_from.h"
#include "varsph/geometry/read_mesh.h"
#include "varsph/geometry/read_polylines.h"
#include "varsph/geometry/sample_curves.h"
#include "varsph/geometry/sample_surface.h"
#include "varsph/geometry/slice_mesh.h"

namespace varsph::geometry {
namespace {

std::string lower_ext(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

std::string fmt(const Eigen::VectorXd& v) {
  std::ostringstream s;
  s.precision(6);
  s << "(";
  for (Eigen::Index i = 0; i < v.size(); ++i) s << (i ? ", " : "") << v[i];
  s << ")";
  return s.str();
}

// The region to be sampled must lie in the domain (an error before sampling: wrong units or transform),
// span a sane number of spacings, and the particle estimate must fit the request's limit.
// lo/hi: bounding box of the geometry (for a volume fill already cut to the clip box).
void check_domain(const BodyRequest& r, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                  std::vector<std::string>& notes) {
  const std::string name = r.mesh.string();
  const Eigen::VectorXd size = hi - lo;
  // more than 1e7 spacings on one axis: beyond any particle budget, and the samplers' int lattice
  // counts would overflow near 2^31
  if ((size.array() / r.spacing > 1e7).any())
    throw GeometryError(r.mesh, "mesh is " + fmt(size) + " m across, more than 1e7 spacings (" +
                                    std::to_string(r.spacing) + " m) on an axis; expected a body of a sane "
                                    "size in metres (wrong units, transform or spacing?)");
  if (r.domain_min.size() == lo.size() && r.domain_max.size() == lo.size()) {
    const Eigen::VectorXd dsize = r.domain_max - r.domain_min;
    const double out = std::max((r.domain_min - lo).maxCoeff(), (hi - r.domain_max).maxCoeff());
    if (out > r.spacing) {
      std::string hint;
      if ((size.array() > 10.0 * dsize.array()).any())
        hint = " (the mesh is more than 10 times the domain's size: is it in millimetres? transform.scale 0.001)";
      throw GeometryError(r.mesh, "mesh bounding box " + fmt(lo) + " .. " + fmt(hi) + " m (after the transform) "
                                      "lies outside the domain " + fmt(r.domain_min) + " .. " + fmt(r.domain_max) +
                                      " m by up to " + std::to_string(out) + " m" + hint +
                                      "; expected a mesh inside domain.min/max (particles may not leave the domain)");
    }
  }
  if ((size.array() / r.spacing > 1e5).any())
    notes.push_back("warning: " + name + ": mesh is " + fmt(size) + " m across, more than 1e5 spacings (" +
                    std::to_string(r.spacing) + " m); check the units");
}

// Particles a body will produce, before sampling: surface measure / dx^(dim-1) x layers, or the enclosed
// measure (within the lattice box) / dx^dim. Refused when above the request's limit.
void check_estimate(const BodyRequest& r, double surface, double enclosed, double box_measure) {
  if (!(r.max_particles > 0)) return;
  const int dim = r.dimension;
  const double dx = r.spacing;
  double est;
  std::string how;
  if (r.fill == "volume") {
    const double m = std::min(std::abs(enclosed), box_measure);
    est = m / std::pow(dx, dim);
    how = "enclosed " + std::string(dim == 3 ? "volume " : "area ") + std::to_string(m) +
          (dim == 3 ? " m^3 / dx^3" : " m^2 / dx^2");
  } else {
    est = surface / std::pow(dx, dim - 1) * r.layers;
    how = std::string(dim == 3 ? "surface area " : "length ") + std::to_string(surface) +
          (dim == 3 ? " m^2 / dx^2" : " m / dx") + " x " + std::to_string(r.layers) + " layers";
  }
  if (!(est <= r.max_particles)) {  // also catches NaN
    std::ostringstream m;
    m.precision(3);
    m << "would produce about " << est << " particles (" << how << ", dx = " << dx << " m), more than the limit of "
      << r.max_particles << "; expected a coarser spacing, a smaller mesh, or a higher particles.max_count";
    throw GeometryError(r.mesh, m.str());
  }
}

void validate(const BodyRequest& r) {
  auto bad = [&](const std::string& what) { throw GeometryError(r.mesh, "invalid body request: " + what); };
  if (r.dimension != 2 && r.dimension != 3) bad("dimension must be 2 or 3, got " + std::to_string(r.dimension));
  if (!(r.spacing > 0) || !std::isfinite(r.spacing)) bad("spacing must be a positive number of metres");
  if (r.fill != "surface" && r.fill != "volume") bad("fill must be \"surface\" or \"volume\", got \"" + r.fill + "\"");
  if (r.layers < 1) bad("layers must be >= 1, got " + std::to_string(r.layers));
  if (r.layer_side != "inside" && r.layer_side != "outside")
    bad("layer_side must be \"inside\" or \"outside\", got \"" + r.layer_side + "\"");
  if (r.clip_min.size() != r.clip_max.size() || (r.clip_min.size() != 0 && r.clip_min.size() != r.dimension))
    bad("clip_min and clip_max must both be empty or both have " + std::to_string(r.dimension) + " entries");
  if (r.exclusion_points.rows() > 0 && r.exclusion_points.cols() != r.dimension)
    bad("exclusion_points must have " + std::to_string(r.dimension) + " columns");
  if (!(r.max_particles >= 0)) bad("max_particles must be >= 0 (0 = no limit)");
  if (!r.transform.allFinite()) bad("transform must hold finite numbers");
  if (!r.section_point.allFinite() || !r.section_normal.allFinite()) bad("section point and normal must be finite");
  if (!r.clip_min.allFinite() || !r.clip_max.allFinite()) bad("clip_min and clip_max must be finite");
  if (r.domain_min.size() != r.domain_max.size() || !r.domain_min.allFinite() || !r.domain_max.allFinite())
    bad("domain_min and domain_max must both be empty or both hold finite numbers");
}

void apply_exclusion(const BodyRequest& r, SampledBody& out) {
  if (r.exclusion_points.rows() == 0 || r.exclusion_distance <= 0) return;
  const Eigen::VectorXi keep = points_far_from(out.positions, r.exclusion_points, r.exclusion_distance);
  const Eigen::Index removed = out.positions.rows() - keep.size();
  Eigen::MatrixXd X(keep.size(), out.positions.cols());
  for (Eigen::Index i = 0; i < keep.size(); ++i) X.row(i) = out.positions.row(keep[i]);
  out.positions = X;
  if (removed > 0)
    out.notes.push_back(r.mesh.string() + ": removed " + std::to_string(removed) + " fluid points closer than " +
                        std::to_string(r.exclusion_distance) + " m to the given boundary points");
}

}  // namespace

SampledBody sample_body(const BodyRequest& r) {
  validate(r);
  SampledBody out;
  const std::string ext = lower_ext(r.mesh);
  const bool volume = r.fill == "volume";
  const int side = r.layer_side == "outside" ? 1 : -1;
  const double dx = r.spacing;
  const int dim = r.dimension;
  const bool mesh_ext = ext == ".stl" || ext == ".obj" || ext == ".off" || ext == ".ply";
  if (dim == 3 && ext == ".poly2d")
    throw GeometryError(r.mesh, "a .poly2d polyline file describes a 2D body; expected a 3D mesh (.stl, .obj, .off, .ply) for dimension 3");

  if (dim == 3) {
    // a surface fill's estimate is checked on the raw soup already: 200k random triangles are refused
    // before the O(#F log #F) repairs
    const auto early = [&](double soup_area) { if (!volume) check_estimate(r, soup_area, 0, 0); };
    TriangleMesh m = read_mesh(r.mesh, r.transform, volume, out.notes, early);
    out.surface_measure = m.area;
    out.enclosed_measure = m.volume;
    Eigen::VectorXd lo = m.V.colwise().minCoeff().transpose(), hi = m.V.colwise().maxCoeff().transpose();
    double box_measure = (hi - lo).prod();
    if (volume && r.clip_min.size() == 3) {  // only the clipped part is sampled
      lo = lo.cwiseMax(r.clip_min);
      hi = hi.cwiseMin(r.clip_max);
      box_measure = (hi - lo).cwiseMax(0.0).prod();
      hi = hi.cwiseMax(lo);
    }
    check_domain(r, lo, hi, out.notes);
    check_estimate(r, m.area, m.volume, box_measure);
    if (volume) {
      if (m.border_edges > 0)
        throw GeometryError(r.mesh, "mesh is not closed (" + std::to_string(m.border_edges) +
                                        " border edges); volume fill needs a closed mesh");
      if (m.self_intersecting) {
        if (!r.allow_self_intersections)
          throw GeometryError(r.mesh, "mesh intersects itself; volume fill needs a closed mesh without "
                                      "self-intersections (or allow_self_intersections = true)");
        out.notes.push_back("warning: " + r.mesh.string() +
                            ": mesh intersects itself; inside test by ray parity (allow_self_intersections)");
      }
      const Eigen::Vector3d bmin = r.clip_min.size() == 3 ? Eigen::Vector3d(r.clip_min) : Eigen::Vector3d(lo);
      const Eigen::Vector3d bmax = r.clip_max.size() == 3 ? Eigen::Vector3d(r.clip_max) : Eigen::Vector3d(hi);
      out.positions = fill_mesh(m, dx, bmin, bmax);
    } else {
      sample_surface(m, dx, r.layers, side, out.positions, out.normals, out.measure, out.layer);
    }
  } else {
    std::vector<Polyline2> loops;
    if (ext == ".poly2d") {
      loops = read_polylines(r.mesh, r.transform, out.notes);
    } else if (mesh_ext) {
      TriangleMesh m = read_mesh(r.mesh, r.transform, false, out.notes);
      if (r.section_normal.norm() == 0)
        throw GeometryError(r.mesh, "invalid body request: section_normal must not be zero");
      loops = slice_mesh(m, r.section_point, r.section_normal);
      if (loops.empty())
        throw GeometryError(r.mesh, "the section plane through " + fmt(r.section_point) + " with normal " +
                                        fmt(r.section_normal) + " does not cut the mesh");
    } else {
      throw GeometryError(r.mesh, "unsupported geometry file extension '" + r.mesh.extension().string() +
                                      "'; expected .poly2d, or .stl/.obj/.off/.ply cut by a section plane");
    }
    Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
    int open = 0;
    for (const auto& l : loops) {
      lo = lo.cwiseMin(l.P.colwise().minCoeff().transpose());
      hi = hi.cwiseMax(l.P.colwise().maxCoeff().transpose());
      const Eigen::Index n = l.P.rows();
      for (Eigen::Index i = 0; i + 1 < n + (l.closed ? 1 : 0); ++i)
        out.surface_measure += (l.P.row((i + 1) % n) - l.P.row(i)).norm();
      if (l.closed) out.enclosed_measure += signed_area(l.P);
      else ++open;
    }
    if (open > 0) out.enclosed_measure = 0;
    double box_measure = (hi - lo).prod();
    if (volume && r.clip_min.size() == 2) {
      lo = lo.cwiseMax(Eigen::Vector2d(r.clip_min));
      hi = hi.cwiseMin(Eigen::Vector2d(r.clip_max));
      box_measure = (hi - lo).cwiseMax(0.0).prod();
      hi = hi.cwiseMax(lo);
    }
    check_domain(r, lo, hi, out.notes);
    check_estimate(r, out.surface_measure, out.enclosed_measure, box_measure);
    if (volume) {
      if (open > 0)
        throw GeometryError(r.mesh, std::to_string(open) + " polyline(s) are open; volume fill needs closed loops");
      const Eigen::Vector2d bmin = r.clip_min.size() == 2 ? Eigen::Vector2d(r.clip_min) : lo;
      const Eigen::Vector2d bmax = r.clip_max.size() == 2 ? Eigen::Vector2d(r.clip_max) : hi;
      out.positions = fill_polygons(loops, dx, bmin, bmax);
    } else {
      sample_curves(loops, dx, r.layers, side, out.positions, out.normals, out.measure, out.layer);
    }
  }
  if (volume) {
    apply_exclusion(r, out);
    out.normals.resize(0, dim);
    out.measure = Eigen::VectorXd::Constant(out.positions.rows(), std::pow(dx, dim));
    out.layer = Eigen::VectorXi::Zero(out.positions.rows());
  }
  return out;
}

}  // namespace varsph::geometry
