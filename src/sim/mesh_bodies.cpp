// The seam between scenes and the CGAL geometry module (its own target; no CGAL header here).
// Mesh body keys (docs/geometry.md): mesh (path relative to the scene file), fill ("surface" |
// "volume"), layers, layer_side ("outside": a tank, layers grow into the wall; "inside": an obstacle),
// transform ({"scale", "rotate_deg", "translate"} or {"matrix": 16 numbers, row-major}), section
// ({"point", "normal"}: 2D cut of a 3D mesh), clip_min/clip_max (volume fill), allow_self_intersections.
#include "sim/mesh_bodies.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <Eigen/Geometry>

#include "core/errors.hpp"
#include "scene/key_suggest.hpp"

#ifdef VARSPH_HAVE_GEOMETRY
#include "varsph/geometry/fill_mesh.h"
#include "varsph/geometry/geometry_error.h"
#include "varsph/geometry/read_mesh.h"
#include "varsph/geometry/sample_body.h"
#endif

namespace varsph {

#ifdef VARSPH_HAVE_GEOMETRY
namespace {

using nlohmann::json;

[[noreturn]] void bad(const std::string& where, const std::string& key, const std::string& expected, const json& got) {
  throw InputError(where + "." + key + ": expected " + expected + ", got " +
                   got.dump(-1, ' ', false, json::error_handler_t::replace));
}

Eigen::Vector3d vec3(const json& j, const std::string& where, const std::string& key, int dim) {
  if (!j.is_array() || (j.size() != 3 && j.size() != std::size_t(dim))) bad(where, key, "an array of 2 or 3 numbers", j);
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < j.size(); ++k) {
    if (!j[k].is_number()) bad(where, key, "numbers", j);
    v[Eigen::Index(k)] = j[k].get<double>();
  }
  return v;
}

Eigen::Matrix4d transform_of(const json& t, const std::string& where, int dim) {
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  if (t.is_null()) return M;
  if (!t.is_object()) bad(where, "transform", "an object {scale, rotate_deg, translate} or {matrix}", t);
  for (auto it = t.begin(); it != t.end(); ++it)
    if (it.key() != "scale" && it.key() != "rotate_deg" && it.key() != "translate" && it.key() != "matrix") {
      const auto guess = scene::closest_key(it.key(), {"scale", "rotate_deg", "translate", "matrix"});
      throw InputError(where + ".transform: unknown key '" + it.key() + "'" +
                       (guess ? " (did you mean '" + *guess + "'?)" : "") + "; expected scale, rotate_deg, translate, matrix");
    }
  if (t.contains("matrix")) {
    if (t.contains("scale") || t.contains("rotate_deg") || t.contains("translate"))  // they would be ignored
      bad(where, "transform", "either {matrix} or {scale, rotate_deg, translate}, not both", t);
    const json& m = t["matrix"];
    if (!m.is_array() || m.size() != 16) bad(where, "transform.matrix", "16 numbers (row-major 4 x 4)", m);
    for (int k = 0; k < 16; ++k) {
      if (!m[std::size_t(k)].is_number()) bad(where, "transform.matrix", "16 numbers (row-major 4 x 4)", m);
      M(k / 4, k % 4) = m[std::size_t(k)].get<double>();
    }
    return M;
  }
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (t.contains("scale")) {
    if (t["scale"].is_number()) S *= t["scale"].get<double>();
    else if (!t["scale"].is_array()) bad(where, "transform.scale", "a positive number or an array of 3", t["scale"]);
    else S = vec3(t["scale"], where, "transform.scale", dim).asDiagonal();
    if (!(S.diagonal().array() > 0).all()) bad(where, "transform.scale", "positive factors", t["scale"]);
  }
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  if (t.contains("rotate_deg")) {  // about x, then y, then z (degrees)
    const Eigen::Vector3d a = vec3(t["rotate_deg"], where, "transform.rotate_deg", 3) * std::numbers::pi / 180.0;
    R = (Eigen::AngleAxisd(a.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(a.y(), Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(a.x(), Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
  }
  M.topLeftCorner<3, 3>() = R * S;
  if (t.contains("translate")) M.topRightCorner<3, 1>() = vec3(t["translate"], where, "transform.translate", dim);
  return M;
}

}  // namespace

template <int D>
void sample_mesh_body(const scene::Scene& s, std::size_t index, double max_particles,
                      std::vector<Vec<D>>& positions, std::vector<Vec<D>>& normals,
                      std::vector<Real>* interface_distance) {
  const scene::BodySpec& b = s.bodies[index];
  const std::string where = s.file.string() + ": bodies." + std::to_string(index);
  const json& m = b.mesh;
  geometry::BodyRequest req;
  if (!m["mesh"].is_string()) bad(where, "mesh", "a file path", m["mesh"]);
  req.mesh = s.file.parent_path() / m["mesh"].get<std::string>();
  if (std::error_code ec; !std::filesystem::exists(req.mesh, ec)) {  // say where it was looked for (issue 35)
    const auto looked = std::filesystem::weakly_canonical(std::filesystem::absolute(req.mesh, ec), ec);
    throw InputError(where + ".mesh: file '" + m["mesh"].get<std::string>() + "' not found: looked for " +
                     looked.string() +
                     (std::filesystem::path(m["mesh"].get<std::string>()).is_relative()
                          ? " (a relative path is taken from the folder of the scene file, " +
                                std::filesystem::weakly_canonical(std::filesystem::absolute(s.file.parent_path(), ec), ec)
                                    .string() + ")"
                          : std::string()) +
                     "; expected an existing .stl, .obj, .off, .ply or .poly2d file");
  }
  req.dimension = D;
  req.spacing = s.spacing;
  for (const char* key : {"fill", "layer_side"})
    if (m.contains(key) && !m[key].is_string()) bad(where, key, "a string", m[key]);
  if (m.contains("allow_self_intersections") && !m["allow_self_intersections"].is_boolean())
    bad(where, "allow_self_intersections", "true or false", m["allow_self_intersections"]);
  req.fill = m.value("fill", b.kind == "fluid" ? std::string("volume") : std::string("surface"));
  if (req.fill != "surface" && req.fill != "volume") bad(where, "fill", "\"surface\" or \"volume\"", m["fill"]);
  req.layers = b.kind == "boundary" ? b.layers : 1;
  req.layer_side = m.value("layer_side", std::string("outside"));
  const bool rigid = b.kind == "rigid";
  if (rigid) {  // a solid in the fluid: layers inside its surface, then (layers 0) its interior filled
    if (m.contains("fill") || m.contains("layer_side"))
      throw InputError(where + ": a rigid mesh body takes no fill or layer_side (its layers grow inside its "
                               "closed surface; `layers` 0 fills it)");
    req.fill = "surface";
    req.layer_side = "inside";
    req.layers = b.layers > 0 ? b.layers : 3;
  }
  if (req.layer_side != "outside" && req.layer_side != "inside")
    bad(where, "layer_side", "\"outside\" (a tank) or \"inside\" (an obstacle)", m["layer_side"]);
  req.transform = transform_of(m.contains("transform") ? m["transform"] : json(), where, D);
  if (m.contains("section")) {
    const json& sec = m["section"];
    if (!sec.is_object() || !sec.contains("point") || !sec.contains("normal"))
      bad(where, "section", "an object {point, normal}", sec);
    req.section_point = vec3(sec["point"], where, "section.point", 3);
    req.section_normal = vec3(sec["normal"], where, "section.normal", 3);
  }
  if (m.contains("clip_min") || m.contains("clip_max")) {
    const Eigen::Vector3d lo = vec3(m.value("clip_min", json::array()), where, "clip_min", D);
    const Eigen::Vector3d hi = vec3(m.value("clip_max", json::array()), where, "clip_max", D);
    req.clip_min = lo.head(D);
    req.clip_max = hi.head(D);
  }
  req.domain_min = Eigen::Map<const Eigen::VectorXd>(s.domain_min.data(), D);
  req.domain_max = Eigen::Map<const Eigen::VectorXd>(s.domain_max.data(), D);
  req.allow_self_intersections = m.value("allow_self_intersections", false);
  req.max_particles = std::max(1.0, max_particles);

  geometry::SampledBody out;
  try {
    out = geometry::sample_body(req);
  } catch (const geometry::GeometryError& e) {
    throw InputError(where + ": " + e.what());
  }
  for (const auto& note : out.notes) std::fprintf(stderr, "varsph: note: %s: %s\n", where.c_str(), note.c_str());
  // our boundary normal points from the wall into the fluid: against the mesh's outward normal for a
  // tank (fluid inside), along it for an obstacle (fluid outside)
  const double sign = req.layer_side == "outside" ? -1.0 : 1.0;
  for (Eigen::Index k = 0; k < out.positions.rows(); ++k) {
    Vec<D> p, n = Vec<D>::Zero();
    for (int a = 0; a < D; ++a) p[a] = Real(out.positions(k, a));
    positions.push_back(p);
    if (out.normals.rows() == out.positions.rows()) {
      for (int a = 0; a < D; ++a) n[a] = Real(sign * out.normals(k, a));
      normals.push_back(n);
      // layer 0 sits on the mesh surface, half a spacing from the fluid (docs/geometry.md)
      if (interface_distance) interface_distance->push_back(Real((double(out.layer[k]) + 0.5) * s.spacing));
    }
  }
  if (rigid && b.layers == 0) {
    // the interior on the volume lattice, clear of the surface layers (no fluid can sit inside a body)
    geometry::BodyRequest vol = req;
    vol.fill = "volume";
    vol.exclusion_points = out.positions;
    vol.exclusion_distance = 0.75 * s.spacing;
    geometry::SampledBody in;
    try {
      in = geometry::sample_body(vol);
    } catch (const geometry::GeometryError& e) {
      throw InputError(where + ": " + e.what());
    }
    for (Eigen::Index k = 0; k < in.positions.rows(); ++k) {
      Vec<D> p;
      for (int a = 0; a < D; ++a) p[a] = Real(in.positions(k, a));
      positions.push_back(p);
      normals.push_back(Vec<D>::Zero());
      if (interface_distance) interface_distance->push_back(Real((double(req.layers) + 0.5) * s.spacing));
    }
  }
}

template <int D>
std::vector<char> inside_mesh_body(const scene::Scene& s, std::size_t index, const std::vector<Vec<D>>& points) {
  const json& m = s.bodies[index].mesh;
  if (D == 2 || m.contains("section") || points.empty()) return {};
  const std::string where = s.file.string() + ": bodies." + std::to_string(index);
  std::vector<std::string> notes;
  geometry::TriangleMesh mesh;
  try {
    mesh = geometry::read_mesh(s.file.parent_path() / m["mesh"].get<std::string>(),
                               transform_of(m.contains("transform") ? m["transform"] : json(), where, D), false, notes);
  } catch (const geometry::GeometryError& e) {
    throw InputError(where + ": " + e.what());
  }
  if (mesh.border_edges > 0) return {};
  Eigen::MatrixXd P(Eigen::Index(points.size()), 3);
  for (std::size_t k = 0; k < points.size(); ++k)
    for (int a = 0; a < 3; ++a) P(Eigen::Index(k), a) = double(points[k][a < D ? a : 0]);
  const Eigen::VectorXi in = geometry::points_inside_mesh(mesh, P);
  std::vector<char> out(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) out[k] = char(in[Eigen::Index(k)]);
  return out;
}

template <int D>
bodies::MassProperties mesh_mass_properties(const scene::Scene& s, std::size_t index) {
  const scene::BodySpec& b = s.bodies[index];
  const std::string where = s.file.string() + ": bodies." + std::to_string(index);
  const json& m = b.mesh;
  if (D == 2 || m.contains("section"))
    throw InputError(where + ": the mass properties of a 2D mesh body are not computed from its outline yet: give "
                             "\"mass\", \"center_of_mass\" and \"inertia\" instead of \"density\"");
  std::vector<std::string> notes;
  geometry::TriangleMesh mesh;
  try {
    mesh = geometry::read_mesh(s.file.parent_path() / m["mesh"].get<std::string>(),
                               transform_of(m.contains("transform") ? m["transform"] : json(), where, D), true, notes);
  } catch (const geometry::GeometryError& e) {
    throw InputError(where + ": " + e.what());
  }
  if (mesh.border_edges > 0)
    throw InputError(where + ".mesh: a rigid body needs a closed mesh (this one has " + std::to_string(mesh.border_edges) +
                     " border edges): its mass, centre of mass and inertia are integrated over the enclosed volume");
  if (mesh.self_intersecting)
    throw InputError(where + ".mesh: a rigid body needs a mesh without self-intersections (its volume is ambiguous)");
  std::vector<Eigen::Vector3d> V(std::size_t(mesh.V.rows()));
  std::vector<Eigen::Vector3i> F(std::size_t(mesh.F.rows()));
  for (Eigen::Index k = 0; k < mesh.V.rows(); ++k) V[std::size_t(k)] = mesh.V.row(k).transpose();
  for (Eigen::Index k = 0; k < mesh.F.rows(); ++k) F[std::size_t(k)] = mesh.F.row(k).transpose();
  return bodies::triangle_mesh_mass(V, F, 1.0);
}

#else

template <int D>
std::vector<char> inside_mesh_body(const scene::Scene&, std::size_t, const std::vector<Vec<D>>&) {
  return {};
}

template <int D>
bodies::MassProperties mesh_mass_properties(const scene::Scene& s, std::size_t index) {
  throw InputError(s.file.string() + ": bodies." + std::to_string(index) +
                   ": mesh bodies need the geometry module, which this build does not include "
                   "(configure with -DVARSPH_BUILD_GEOMETRY=ON)");
}

template <int D>
void sample_mesh_body(const scene::Scene& s, std::size_t index, double, std::vector<Vec<D>>&,
                      std::vector<Vec<D>>&, std::vector<Real>*) {
  throw InputError(s.file.string() + ": bodies." + std::to_string(index) +
                   ": mesh bodies need the geometry module, which this build does not include "
                   "(configure with -DVARSPH_BUILD_GEOMETRY=ON)");
}

#endif

template std::vector<char> inside_mesh_body<2>(const scene::Scene&, std::size_t, const std::vector<Vec<2>>&);
template std::vector<char> inside_mesh_body<3>(const scene::Scene&, std::size_t, const std::vector<Vec<3>>&);
template bodies::MassProperties mesh_mass_properties<2>(const scene::Scene&, std::size_t);
template bodies::MassProperties mesh_mass_properties<3>(const scene::Scene&, std::size_t);
template void sample_mesh_body<2>(const scene::Scene&, std::size_t, double, std::vector<Vec<2>>&,
                                  std::vector<Vec<2>>&, std::vector<Real>*);
template void sample_mesh_body<3>(const scene::Scene&, std::size_t, double, std::vector<Vec<3>>&,
                                  std::vector<Vec<3>>&, std::vector<Real>*);

}  // namespace varsph
