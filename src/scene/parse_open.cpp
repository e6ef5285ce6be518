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

OpenZoneSpec parse_zone(JsonReader& r, const std::string& base, const Scene& s) {
  const int d = s.dimension;
  r.expect_keys(base, {"name", "kind", "min", "max", "direction", "velocity", "pressure", "water_level"});
  r.expect_keys(at(base, "velocity"), {"profile", "value", "peak", "file", "ramp", "roughness"});
  OpenZoneSpec z;
  z.name = r.text(at(base, "name"), std::nullopt);
  if (z.name.empty() || z.name.find_first_of("/\\ ") != std::string::npos)
    r.fail_got(at(base, "name"), "a non-empty name without spaces or slashes", json(z.name));
  z.kind = r.choice(at(base, "kind"), std::nullopt, {"inlet", "outlet"});
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
    r.fail_got(at(base, "direction"), "a unit vector along an axis, e.g. [1, 0] (oblique zones are not supported yet)",
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
    } else if (z.profile == "parabolic") {
      if (d != 2) r.fail_got(at(base, "velocity.profile"), "\"uniform\" or \"file\" in 3D (\"parabolic\" is the 2D plane profile)",
                             json(z.profile));
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
        if (boxes_overlap(s.open_boundaries[j], s.open_boundaries[k], s.dimension))
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
