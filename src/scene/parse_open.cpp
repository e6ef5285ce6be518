#include "scene/parse_open.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/errors.hpp"

namespace varsph::scene {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
std::string at(const std::string& base, const std::string& key) { return base + "." + key; }

// a CSV file of rows "time,value" (a header line of text is allowed), checked row by row: numbers, finite,
// strictly increasing times, and `bad(value)` (empty when the value is acceptable, else what is expected)
template <class Check>
void read_series(JsonReader& r, const std::string& key, const std::filesystem::path& file, const std::string& value,
                 std::vector<double>& ts, std::vector<double>& vs, Check bad) {
  std::ifstream in(file);
  if (!in) r.fail_got(key, "a readable CSV file of rows time," + value + " (path relative to the scene file)", json(file.string()));
  std::string line;
  long row = 0;
  while (std::getline(in, line)) {
    ++row;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    for (char& c : line)
      if (c == ',' || c == ';') c = ' ';
    std::istringstream ls(line);
    std::string a, b;
    ls >> a >> b;
    char* end = nullptr;
    const double t = std::strtod(a.c_str(), &end);
    const bool number_t = !a.empty() && end && *end == '\0';
    if (!number_t && ts.empty() && row == 1) continue;  // a header line
    const double u = std::strtod(b.c_str(), &end);
    const bool number_u = !b.empty() && end && *end == '\0';
    const std::string where = file.string() + " line " + std::to_string(row);
    if (!number_t || !number_u) r.fail_got(key, "rows of two numbers time," + value + " (" + where + ")", json(line));
    if (!std::isfinite(t) || !std::isfinite(u)) r.fail_got(key, "finite times and " + value + "s (" + where + ")", json(line));
    if (!ts.empty() && !(t > ts.back()))
      r.fail_got(key, "strictly increasing times (" + where + ": " + std::to_string(t) + " after " +
                          std::to_string(ts.back()) + ")", json(line));
    if (const std::string e = bad(u); !e.empty()) r.fail_got(key, e + " (" + where + ")", json(line));
    ts.push_back(t);
    vs.push_back(u);
  }
  if (ts.empty()) r.fail_got(key, "at least one row time," + value, json(file.string()));
}

// linear in time between rows, held beyond the ends
double interpolate(const std::vector<double>& ts, const std::vector<double>& vs, double t) {
  if (t <= ts.front()) return vs.front();
  if (t >= ts.back()) return vs.back();
  std::size_t k = 1;
  while (ts[k] < t) ++k;
  const double w = (t - ts[k - 1]) / (ts[k] - ts[k - 1]);
  return vs[k - 1] + w * (vs[k] - vs[k - 1]);
}

// `water_level` of an inlet: a number [m] or {"file": CSV time,level}; every level strictly above the zone's
// bottom (the bed) and at most its top on the vertical axis (the last); the zone's direction horizontal
void parse_water_level(JsonReader& r, const std::string& base, const Scene& s, OpenZoneSpec& z) {
  const int v = s.dimension - 1;
  const std::string key = at(base, "water_level");
  const json* wl = r.raw(key);
  if (z.kind != "inlet") r.fail(key, "no water level on an outlet (a free-surface level is an inlet key)");
  if (z.oblique) r.fail(key, "no water level on an oblique zone yet (a free-surface inlet is a box zone given by min/max)");
  if (z.axis == v)
    r.fail_got(at(base, "direction"), "a horizontal direction for a zone with a water_level (the level is a coordinate on "
                                      "axis " + std::to_string(v) + ", the vertical)", json(z.direction));
  const double bed = z.min[v], top = z.max[v];
  const auto bad = [&](double level) -> std::string {
    std::ostringstream m;
    if (!std::isfinite(level)) return "a finite water level [m]";
    if (!(level > bed)) {
      m << "a water level above the zone's bottom (the bed) at " << bed << " m on axis " << v << " (" << level
        << " is at or below it: the inlet would be dry)";
      return m.str();
    }
    if (level > top + 1e-12) {
      m << "a water level at most the zone's top at " << top << " m on axis " << v << " (" << level
        << " is above it: raise open_boundaries max or lower the level)";
      return m.str();
    }
    return "";
  };
  z.surface = true;
  if (wl->is_object()) {
    r.expect_keys(key, {"file"});
    const std::string f = r.text(at(key, "file"), std::nullopt);
    std::filesystem::path p(f);
    if (p.is_relative()) p = s.file.parent_path() / p;
    read_series(r, at(key, "file"), p, "level", z.level_t, z.level_z, bad);
    z.level = z.level_z.front();
  } else {
    z.level = r.number(key, std::nullopt, -kInf, kInf, "water level on the vertical axis [m]");
    if (const std::string e = bad(z.level); !e.empty()) r.fail_got(key, e, json(z.level));
  }
}

// A zone's corners (2^D) in the scene's coordinates: the box's, or the oblique zone's (interface rectangle
// through `center`, swept `depth` against the normal)
std::vector<std::vector<double>> corners(const OpenZoneSpec& z, int d) {
  std::vector<std::vector<double>> out;
  for (int m = 0; m < (1 << d); ++m) {
    std::vector<double> p(static_cast<std::size_t>(d));
    for (int a = 0; a < d; ++a) {
      const bool up = (m >> a) & 1;
      if (!z.oblique) {
        p[std::size_t(a)] = up ? z.max[std::size_t(a)] : z.min[std::size_t(a)];
        continue;
      }
      double v = z.center[std::size_t(a)] - ((m & 1) ? z.depth * z.direction[std::size_t(a)] : 0.0);
      if (!z.plane_lo.empty()) {  // a polygon or disc: its in-plane bounding rectangle from plane_lo
        for (int k = 0; k + 1 < d; ++k)
          v += (z.plane_lo[std::size_t(k)] + (((m >> (k + 1)) & 1) ? z.width[std::size_t(k)] : 0.0)) *
               z.tangents[std::size_t(k)][std::size_t(a)];
        p[std::size_t(a)] = v;
        continue;
      }
      for (int k = 0; k + 1 < d; ++k)
        v += (((m >> (k + 1)) & 1) ? 0.5 : -0.5) * z.width[std::size_t(k)] * z.tangents[std::size_t(k)][std::size_t(a)];
      p[std::size_t(a)] = v;
    }
    out.push_back(std::move(p));
  }
  return out;
}

// A 3D oblique zone's polygon interface (`polygon`): at least 3 in-plane vertices [a, b] [m] along the tangents
// about `center`, either orientation, a simple polygon (no two edges cross or touch but neighbours at their
// shared vertex) of non-zero area. Sets the bounding rectangle (plane_lo, width) the lattice covers.
void parse_polygon(JsonReader& r, const std::string& base, const Scene& s, OpenZoneSpec& z) {
  const std::string key = at(base, "polygon");
  const json* raw = r.raw(key);
  if (!raw->is_array() || raw->size() < 3)
    r.fail_got(key, "a polygon of at least 3 vertices [[a, b], ...] in metres along tangent and direction x tangent about center",
               *raw);
  const std::size_t n = raw->size();
  for (std::size_t k = 0; k < n; ++k) {
    const auto v = r.vector(at(key, std::to_string(k)), 2, std::nullopt, "an in-plane vertex [a, b] [m]");
    z.polygon.push_back({v[0], v[1]});
  }
  r.subtree(key, *raw);
  double lo[2] = {kInf, kInf}, hi[2] = {-kInf, -kInf}, area2 = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const auto& p = z.polygon[k];
    const auto& q = z.polygon[(k + 1) % n];
    area2 += p[0] * q[1] - q[0] * p[1];  // the shoelace formula: twice the signed area
    for (int c = 0; c < 2; ++c) lo[c] = std::min(lo[c], p[std::size_t(c)]), hi[c] = std::max(hi[c], p[std::size_t(c)]);
  }
  const double size = std::max(hi[0] - lo[0], hi[1] - lo[1]);
  if (!(std::abs(area2) > 1e-9 * size * size))
    r.fail_got(key, "a polygon of non-zero area (its vertices lie on a line or on a point)", *raw);
  // simple: no two edges meet except neighbours at their shared vertex (orientation tests; collinear overlaps
  // and touching count as meeting)
  const auto orient = [](const std::array<double, 2>& a, const std::array<double, 2>& b, const std::array<double, 2>& c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  };
  const double eps = 1e-12 * size * size;
  const auto on_segment = [&](const std::array<double, 2>& a, const std::array<double, 2>& b, const std::array<double, 2>& c) {
    return std::abs(orient(a, b, c)) <= eps && std::min(a[0], b[0]) - 1e-12 * size <= c[0] && c[0] <= std::max(a[0], b[0]) + 1e-12 * size &&
           std::min(a[1], b[1]) - 1e-12 * size <= c[1] && c[1] <= std::max(a[1], b[1]) + 1e-12 * size;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const auto &a = z.polygon[i], &b = z.polygon[(i + 1) % n];
    if (a == b) r.fail_got(key, "distinct consecutive vertices (vertex " + std::to_string(i) + " repeats)", *raw);
    for (std::size_t j = i + 1; j < n; ++j) {
      const bool adjacent = j == i + 1 || (i == 0 && j == n - 1);
      const auto &c = z.polygon[j], &e = z.polygon[(j + 1) % n];
      bool meet;
      if (adjacent) {  // neighbours share one vertex: they meet elsewhere only if they fold back on each other
        const auto& shared = j == i + 1 ? b : a;
        const auto& other_i = j == i + 1 ? a : b;
        const auto& other_j = j == i + 1 ? e : c;
        meet = on_segment(shared, other_j, other_i) || on_segment(shared, other_i, other_j);
      } else {
        const double o1 = orient(a, b, c), o2 = orient(a, b, e), o3 = orient(c, e, a), o4 = orient(c, e, b);
        meet = ((o1 > eps && o2 < -eps) || (o1 < -eps && o2 > eps)) && ((o3 > eps && o4 < -eps) || (o3 < -eps && o4 > eps));
        meet = meet || on_segment(a, b, c) || on_segment(a, b, e) || on_segment(c, e, a) || on_segment(c, e, b);
      }
      if (meet)
        r.fail_got(key, "a simple polygon (edges " + std::to_string(i) + " and " + std::to_string(j) +
                            " cross or touch: it intersects itself)", *raw);
    }
  }
  if (!(hi[0] - lo[0] >= s.spacing * (1 - 1e-9) || hi[1] - lo[1] >= s.spacing * (1 - 1e-9)))
    r.fail_got(key, "a polygon at least a spacing across", *raw);
  z.interface = "polygon";
  z.plane_lo = {lo[0], lo[1]};
  z.width = {hi[0] - lo[0], hi[1] - lo[1]};
}

// Keys of an oblique plane zone (docs/scene.md "Open boundaries"): center, direction (any non-zero vector,
// normalised), depth and width multiples of the spacing (the zone's own lattice), 3D tangent normal to it.
void parse_oblique(JsonReader& r, const std::string& base, const Scene& s, OpenZoneSpec& z) {
  const int d = s.dimension;
  const double dx = s.spacing;
  for (const char* k : {"min", "max"})
    if (r.raw(at(base, k)))
      r.fail(at(base, k), "either min/max (a box zone) or center/direction/depth/width (an oblique plane zone), not both");
  z.oblique = true;
  z.center = r.vector(at(base, "center"), d, std::nullopt, "a point on the zone's interface: the centre of its face [m]");
  z.direction = r.vector(at(base, "direction"), d, std::nullopt,
                         "normal of the interface from the zone into the fluid (any orientation; normalised)");
  double nn = 0;
  for (double c : z.direction) nn += c * c;
  nn = std::sqrt(nn);
  if (!(nn > 1e-12) || !std::isfinite(nn))
    r.fail_got(at(base, "direction"), "a non-zero, finite normal from the zone into the fluid", json(z.direction));
  for (double& c : z.direction) c /= nn;
  z.axis = 0;
  for (int a = 1; a < d; ++a)
    if (std::abs(z.direction[std::size_t(a)]) > std::abs(z.direction[std::size_t(z.axis)])) z.axis = a;
  z.sign = z.direction[std::size_t(z.axis)] > 0 ? 1 : -1;
  const auto multiple = [&](const std::string& key, double v, const std::string& what) {
    const double cells = v / dx;
    if (std::abs(cells - std::round(cells)) > 1e-6 || std::round(cells) < 1)
      r.fail_got(key, what + " that is a positive multiple of particles.spacing (the zone's lattice; " +
                          std::to_string(cells) + " spacings)", json(v));
  };
  z.depth = r.positive(at(base, "depth"), std::nullopt, "extent of the zone against its direction [m]");
  multiple(at(base, "depth"), z.depth, "a depth");
  if (d == 2) {
    for (const char* k : {"polygon", "radius"})
      if (r.raw(at(base, k)))
        r.fail(at(base, k), "no `" + std::string(k) + "` in 2D (the 2D interface is a segment: give its width)");
    z.width = {r.positive(at(base, "width"), std::nullopt, "width of the interface along its tangent [m]")};
    multiple(at(base, "width"), z.width[0], "a width");
    if (r.raw(at(base, "tangent")))
      r.fail(at(base, "tangent"), "no tangent in 2D (the interface's tangent is the direction turned by +90 degrees)");
    z.tangents = {{-z.direction[1], z.direction[0]}};
  } else {
    const bool has_poly = r.raw(at(base, "polygon")) != nullptr, has_disc = r.raw(at(base, "radius")) != nullptr;
    if (int(has_poly) + int(has_disc) + int(r.raw(at(base, "width")) != nullptr) > 1)
      r.fail(at(base, has_poly ? "polygon" : "radius"), "one interface shape: width (a rectangle), polygon or radius (a disc)");
    if (has_poly) {
      parse_polygon(r, base, s, z);
    } else if (has_disc) {
      z.interface = "disc";
      z.radius = r.positive(at(base, "radius"), std::nullopt, "radius of the disc interface about center [m]");
      if (!(z.radius >= dx))
        r.fail_got(at(base, "radius"), "a radius of at least particles.spacing (" + std::to_string(dx) + " m)", json(z.radius));
      z.width = {2 * z.radius, 2 * z.radius};
      z.plane_lo = {-z.radius, -z.radius};
    } else {
      z.width = r.vector(at(base, "width"), 2, std::nullopt, "widths of the interface rectangle along tangent and direction x tangent [m]");
      for (int k = 0; k < 2; ++k) {
        if (!(z.width[std::size_t(k)] > 0))
          r.fail_got(at(base, "width"), "widths > 0 [m]", json(z.width));
        multiple(at(base, "width"), z.width[std::size_t(k)], "widths each");
      }
    }
    std::vector<double> t = r.vector(at(base, "tangent"), 3, std::nullopt,
                                     "the interface rectangle's first side, normal to direction (normalised)");
    double tn = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    if (!(tn > 1e-12) || !std::isfinite(tn)) r.fail_got(at(base, "tangent"), "a non-zero, finite vector", json(t));
    for (double& c : t) c /= tn;
    const auto& n = z.direction;
    const double dot = t[0] * n[0] + t[1] * n[1] + t[2] * n[2];
    if (std::abs(dot) > 1e-6)
      r.fail_got(at(base, "tangent"), "a vector normal to direction (its normalised dot product with it is " +
                                          std::to_string(dot) + ")", json(t));
    const std::vector<double> t2 = {n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0]};
    z.tangents = {t, t2};
  }
  for (int a = 0; a < d; ++a)
    if (s.periodic[std::size_t(a)] && std::abs(z.direction[std::size_t(a)]) > 1e-12)
      r.fail_got(at(base, "direction"), "a normal with no component on a periodic axis (domain.periodic is true on axis " +
                                            std::to_string(a) + ")", json(z.direction));
  // a polygon's vertices and a disc's rim inside the domain, at the interface and at the zone's depth
  if (z.interface != "rectangle") {
    std::vector<std::vector<double>> pts;
    const auto& t1 = z.tangents[0];
    const auto& t2 = z.tangents[1];
    if (z.interface == "polygon") {
      for (const auto& q : z.polygon) {
        std::vector<double> p(3);
        for (int a = 0; a < 3; ++a) p[std::size_t(a)] = z.center[std::size_t(a)] + q[0] * t1[std::size_t(a)] + q[1] * t2[std::size_t(a)];
        pts.push_back(p);
      }
    } else {  // the disc's extent on axis a: R sqrt(1 - n_a^2) about the centre
      for (int a = 0; a < 3; ++a)
        for (const double sg : {-1.0, 1.0}) {
          std::vector<double> p = z.center;
          p[std::size_t(a)] += sg * z.radius * std::sqrt(std::max(0.0, 1 - z.direction[std::size_t(a)] * z.direction[std::size_t(a)]));
          pts.push_back(p);
        }
    }
    const std::string key = at(base, z.interface == "polygon" ? "polygon" : "radius");
    z.min.assign(std::size_t(d), kInf);
    z.max.assign(std::size_t(d), -kInf);
    for (const double back : {0.0, z.depth})
      for (std::size_t k = 0; k < pts.size(); ++k)
        for (int a = 0; a < d; ++a) {
          const double v = pts[k][std::size_t(a)] - back * z.direction[std::size_t(a)];
          z.min[std::size_t(a)] = std::min(z.min[std::size_t(a)], v);
          z.max[std::size_t(a)] = std::max(z.max[std::size_t(a)], v);
          if (v < s.domain_min[std::size_t(a)] - 1e-12 || v > s.domain_max[std::size_t(a)] + 1e-12) {
            std::ostringstream m;
            m << "a zone inside domain.min/max (" << (z.interface == "polygon" ? "vertex " + std::to_string(k) : std::string("the disc's rim"))
              << (back > 0 ? " swept to the zone's depth" : "") << " lies at " << v << " on axis " << a << ")";
            r.fail_got(key, m.str(), z.interface == "polygon" ? *r.raw(key) : json(z.radius));
          }
        }
  } else {  // the zone inside the domain; its bounding box in min/max
    z.min.assign(std::size_t(d), kInf);
    z.max.assign(std::size_t(d), -kInf);
    for (const auto& p : corners(z, d))
      for (int a = 0; a < d; ++a) {
        z.min[std::size_t(a)] = std::min(z.min[std::size_t(a)], p[std::size_t(a)]);
        z.max[std::size_t(a)] = std::max(z.max[std::size_t(a)], p[std::size_t(a)]);
        if (p[std::size_t(a)] < s.domain_min[std::size_t(a)] - 1e-12 || p[std::size_t(a)] > s.domain_max[std::size_t(a)] + 1e-12)
          r.fail_got(at(base, "center"), "a zone inside domain.min/max (a corner of the zone lies at " +
                                             std::to_string(p[std::size_t(a)]) + " on axis " + std::to_string(a) + ")",
                     json(z.center));
      }
  }
  // the interface must have domain beyond it: a spacing past the face's centre along the direction
  for (int a = 0; a < d; ++a) {
    const double q = z.center[std::size_t(a)] + dx * z.direction[std::size_t(a)];
    if (!(q > s.domain_min[std::size_t(a)] && q < s.domain_max[std::size_t(a)]))
      r.fail_got(at(base, "direction"), "a direction from the zone into the domain (a spacing beyond the face's centre lies "
                                        "outside the domain on axis " + std::to_string(a) + ")", json(z.direction));
  }
}

OpenZoneSpec parse_zone(JsonReader& r, const std::string& base, const Scene& s) {
  const int d = s.dimension;
  r.expect_keys(base, {"name", "kind", "min", "max", "direction", "velocity", "pressure", "water_level", "center", "depth",
                       "width", "tangent", "polygon", "radius"});
  r.expect_keys(at(base, "velocity"), {"profile", "value", "peak", "file", "ramp", "roughness"});
  OpenZoneSpec z;
  z.name = r.text(at(base, "name"), std::nullopt);
  if (z.name.empty() || z.name.find_first_of("/\\ ") != std::string::npos)
    r.fail_got(at(base, "name"), "a non-empty name without spaces or slashes", json(z.name));
  z.kind = r.choice(at(base, "kind"), std::nullopt, {"inlet", "outlet"});
  if (r.raw(at(base, "center"))) {
    parse_oblique(r, base, s, z);
  } else {
    for (const char* k : {"depth", "width", "tangent", "polygon", "radius"})
      if (r.raw(at(base, k)))
        r.fail(at(base, k), "no `" + std::string(k) + "` on a box zone given by min/max (an oblique plane zone is given by "
                            "center, direction, depth and width instead)");
    z.min = r.vector(at(base, "min"), d, std::nullopt, "lower corner of the zone [m]");
    z.max = r.vector(at(base, "max"), d, std::nullopt, "upper corner of the zone [m]");
    for (int a = 0; a < d; ++a) {
      if (!(z.max[a] > z.min[a])) r.fail(at(base, "max"), "max > min on every axis (axis " + std::to_string(a) + " is empty)");
      const double cells = (z.max[a] - z.min[a]) / s.spacing;
      if (std::abs(cells - std::round(cells)) > 1e-6)
        r.fail_got(at(base, "max"), "a box whose extent on every axis is a multiple of particles.spacing (axis " +
                                        std::to_string(a) + ": " + std::to_string(cells) + " spacings)", json(z.max));
      if (z.min[a] < s.domain_min[a] - 1e-12 || z.max[a] > s.domain_max[a] + 1e-12)
        r.fail_got(at(base, "max"), "a zone inside domain.min/max (axis " + std::to_string(a) + ")", json(z.max));
    }
    z.direction = r.vector(at(base, "direction"), d, std::nullopt, "unit vector from the zone into the fluid");
    int nonzero = 0;
    for (int a = 0; a < d; ++a)
      if (z.direction[a] != 0) {
        ++nonzero;
        z.axis = a;
      }
    if (nonzero != 1 || std::abs(z.direction[z.axis]) != 1.0)
      r.fail_got(at(base, "direction"), "a unit vector along an axis, e.g. [1, 0], for a box zone (min/max); an oblique zone is given by center, "
                 "direction, depth and width instead",
                 json(z.direction));
    z.sign = z.direction[z.axis];
    if (s.periodic[z.axis])
      r.fail(at(base, "direction"), "an axis that is not periodic (domain.periodic is true on axis " + std::to_string(z.axis) + ")");
    // the interface (the face the direction points to) must have fluid beyond it: inside the domain
    const double face = z.sign > 0 ? z.max[z.axis] : z.min[z.axis];
    if (!(face > s.domain_min[z.axis] + 0.5 * s.spacing && face < s.domain_max[z.axis] - 0.5 * s.spacing))
      r.fail_got(at(base, "direction"), "a direction from the zone into the domain (the zone's face at " + std::to_string(face) +
                                            " on axis " + std::to_string(z.axis) + " has no domain beyond it)",
                 json(z.direction));
  }
  if (r.raw(at(base, "water_level"))) parse_water_level(r, base, s, z);
  if (z.kind == "inlet") {
    z.profile = r.choice(at(base, "velocity.profile"), "uniform", {"uniform", "parabolic", "log_law", "file"});
    if (z.profile == "uniform") {
      z.speed = r.number(at(base, "velocity.value"), std::nullopt, -kInf, kInf, "inflow speed along the direction [m/s]");
      if (!(z.speed > 0))
        r.fail_got(at(base, "velocity.value"), "an inflow speed > 0 along the zone's direction (a speed <= 0 points out of the domain)",
                   json(z.speed));
    } else if (z.profile == "log_law") {
      if (!z.surface)
        r.fail_got(at(base, "velocity.profile"), "\"uniform\", \"parabolic\" or \"file\" (\"log_law\" is the profile of a "
                                                  "free-surface inlet: name its water_level)", json(z.profile));
      z.speed = r.number(at(base, "velocity.value"), std::nullopt, -kInf, kInf, "depth-mean inflow speed along the direction [m/s]");
      if (!(z.speed > 0))
        r.fail_got(at(base, "velocity.value"), "an inflow speed > 0 along the zone's direction (a speed <= 0 points out of the domain)",
                   json(z.speed));
      z.roughness = r.number(at(base, "velocity.roughness"), std::nullopt, -kInf, kInf, "roughness length z0 of the bed [m]");
      // the depth mean of ln(s / z0) over the water depth is ln(H / z0) - 1: it must be positive
      const double depth_min = (z.level_t.empty() ? z.level : *std::min_element(z.level_z.begin(), z.level_z.end())) -
                               z.min[std::size_t(d - 1)];
      if (!(z.roughness > 0 && depth_min > std::exp(1.0) * z.roughness))
        r.fail_got(at(base, "velocity.roughness"), "a roughness length z0 > 0 and below the water depth / e (" +
                                                      std::to_string(depth_min / std::exp(1.0)) + " m here)", json(z.roughness));
    } else if (z.profile == "parabolic" && z.surface) {
      z.speed = r.number(at(base, "velocity.peak"), std::nullopt, -kInf, kInf,
                         "surface speed of the open-channel profile u = peak (2 s / H - s^2 / H^2) [m/s]");
      if (!(z.speed > 0))
        r.fail_got(at(base, "velocity.peak"), "a peak speed > 0 along the zone's direction (a speed <= 0 points out of the domain)",
                   json(z.speed));
    } else if (z.profile == "parabolic" && z.interface == "disc") {
      z.speed = r.number(at(base, "velocity.peak"), std::nullopt, -kInf, kInf,
                         "centre-line speed of the pipe profile u = peak (1 - r^2 / R^2) on the disc [m/s]");
      if (!(z.speed > 0))
        r.fail_got(at(base, "velocity.peak"), "a peak speed > 0 along the zone's direction (a speed <= 0 points out of the domain)",
                   json(z.speed));
    } else if (z.profile == "parabolic") {
      if (d != 2)
        r.fail_got(at(base, "velocity.profile"), "\"uniform\" or \"file\" in 3D on a " + z.interface +
                                                  " (\"parabolic\" is the 2D plane profile, or in 3D the pipe profile of a disc "
                                                  "zone given by radius)", json(z.profile));
      z.speed = r.number(at(base, "velocity.peak"), std::nullopt, -kInf, kInf,
                         "peak speed of u = 4 u_peak s (W - s) / W^2 across the zone [m/s]");
      if (!(z.speed > 0))
        r.fail_got(at(base, "velocity.peak"), "a peak speed > 0 along the zone's direction (a speed <= 0 points out of the domain)",
                   json(z.speed));
    } else {
      const std::string f = r.text(at(base, "velocity.file"), std::nullopt);
      std::filesystem::path p(f);
      if (p.is_relative()) p = s.file.parent_path() / p;
      read_series(r, at(base, "velocity.file"), p, "speed", z.series_t, z.series_u, [](double u) -> std::string {
        return u < 0 ? "inflow speeds >= 0 along the zone's direction (a negative speed points out of the domain)" : "";
      });
    }
    // a smooth start: an inflow switched on at once sends a pressure wave of rho c0 u through the domain
    // (the water hammer), which an inlet (fixed velocity) and an outlet (fixed pressure) trap and ring
    z.ramp = r.number(at(base, "velocity.ramp"), 0.0, 0, kInf, "time over which the inflow rises from 0 [s]");
  }
  const json* pr = r.raw(at(base, "pressure"));
  if (z.surface && (!pr || (pr->is_string() && pr->get<std::string>() == "hydrostatic"))) {
    // a free-surface inlet: hydrostatic from its level by default (DualSPHysics' rhopmode hydrostatic)
    r.text(at(base, "pressure"), "hydrostatic");
    const double gz = s.gravity[std::size_t(d - 1)];
    if (!(gz < 0))
      r.fail_got(at(base, "pressure"), "gravity with a downward component on the vertical axis " + std::to_string(d - 1) +
                                           " for a hydrostatic inlet (or \"extrapolated\", or a number [Pa])",
                 json("hydrostatic"));
    z.hydrostatic = true;
    z.pressure_extrapolated = false;
  } else if (pr && pr->is_string()) {
    r.choice(at(base, "pressure"), std::nullopt, {"extrapolated"});  // or a number [Pa]; "hydrostatic" with a water_level
    z.pressure_extrapolated = true;
  } else if (pr) {
    z.pressure = r.number(at(base, "pressure"), std::nullopt, -kInf, kInf, "prescribed pressure [Pa]");
    z.pressure_extrapolated = false;
  } else if (z.kind == "inlet") {
    r.text(at(base, "pressure"), "extrapolated");
    z.pressure_extrapolated = true;
  } else {
    z.pressure = r.number(at(base, "pressure"), 0.0, -kInf, kInf, "prescribed pressure [Pa]");
    z.pressure_extrapolated = false;
  }
  return z;
}

bool boxes_overlap(const OpenZoneSpec& a, const OpenZoneSpec& b, int d) {
  for (int k = 0; k < d; ++k)
    if (!(a.min[k] < b.max[k] - 1e-12 && b.min[k] < a.max[k] - 1e-12)) return false;
  return true;
}

// Two zones of which one at least is oblique: oriented boxes overlap unless an axis separates them (the
// separating axis theorem: the faces' normals, and in 3D their cross products), touching faces allowed
bool zones_overlap(const OpenZoneSpec& a, const OpenZoneSpec& b, int d) {
  if (!a.oblique && !b.oblique) return boxes_overlap(a, b, d);
  const auto normals = [d](const OpenZoneSpec& z) {
    std::vector<std::vector<double>> out;
    if (!z.oblique) {
      for (int k = 0; k < d; ++k) {
        std::vector<double> e(std::size_t(d), 0.0);
        e[std::size_t(k)] = 1;
        out.push_back(e);
      }
    } else {
      out.push_back(z.direction);
      for (const auto& t : z.tangents) out.push_back(t);
    }
    return out;
  };
  std::vector<std::vector<double>> axes = normals(a);
  const auto nb = normals(b);
  axes.insert(axes.end(), nb.begin(), nb.end());
  if (d == 3)
    for (const auto& u : normals(a))
      for (const auto& v : nb) {
        const std::vector<double> c = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        if (c[0] * c[0] + c[1] * c[1] + c[2] * c[2] > 1e-12) axes.push_back(c);
      }
  const auto ca = corners(a, d), cb = corners(b, d);
  for (const auto& ax : axes) {
    double la = kInf, ha = -kInf, lb = kInf, hb = -kInf, len = 0;
    for (int k = 0; k < d; ++k) len += ax[std::size_t(k)] * ax[std::size_t(k)];
    len = std::sqrt(len);
    for (const auto& p : ca) {
      double q = 0;
      for (int k = 0; k < d; ++k) q += p[std::size_t(k)] * ax[std::size_t(k)] / len;
      la = std::min(la, q), ha = std::max(ha, q);
    }
    for (const auto& p : cb) {
      double q = 0;
      for (int k = 0; k < d; ++k) q += p[std::size_t(k)] * ax[std::size_t(k)] / len;
      lb = std::min(lb, q), hb = std::max(hb, q);
    }
    if (!(la < hb - 1e-9 && lb < ha - 1e-9)) return false;  // separated (or touching) along this axis
  }
  return true;
}

}  // namespace

double OpenZoneSpec::level_at(double t) const { return level_t.empty() ? level : interpolate(level_t, level_z, t); }

double OpenZoneSpec::speed_at(double t) const {
  double u = speed;
  if (profile == "file") u = interpolate(series_t, series_u, t);
  if (ramp > 0 && t < ramp) u *= t <= 0 ? 0.0 : 0.5 * (1 - std::cos(3.14159265358979323846 * t / ramp));
  return u;
}

void parse_open_boundaries(JsonReader& r, Scene& s) {
  const std::size_t n = r.array_size("open_boundaries");
  for (std::size_t k = 0; k < n; ++k) {
    const std::string base = "open_boundaries." + std::to_string(k);
    try {
      s.open_boundaries.push_back(parse_zone(r, base, s));
      for (std::size_t j = 0; j < k; ++j) {
        if (s.open_boundaries[j].name == s.open_boundaries[k].name)
          r.fail_got(at(base, "name"), "a name no other zone has", json(s.open_boundaries[k].name));
        if (zones_overlap(s.open_boundaries[j], s.open_boundaries[k], s.dimension))
          r.fail(at(base, "min"), "a zone that does not overlap zone '" + s.open_boundaries[j].name + "' (open_boundaries." +
                                      std::to_string(j) + ")");
      }
    } catch (const InputError& e) {
      // name the zone after its key, as the checks after the build do: "key 'open_boundaries.K.x' (zone 'N'):"
      const json* name = r.raw(at(base, "name"));
      std::string m = e.what();
      const std::string lead = "key '" + base;
      const std::size_t p = m.find(lead);
      const std::size_t q = p == std::string::npos ? p : m.find('\'', p + lead.size());
      if (!name || !name->is_string() || q == std::string::npos || m.compare(q + 1, 2, ": ") != 0) throw;
      m.insert(q + 1, " (zone '" + name->get<std::string>() + "')");
      throw InputError(m);
    }
  }
}

}  // namespace varsph::scene
