// Polygon and disc interfaces of 3D oblique open-boundary zones (issue 32; sim/open_boundaries.hpp,
// docs/open_boundaries.md "Polygon and disc interfaces"): the inside test (a square polygon is the rectangle
// zone, node for node and bit for bit; a triangle, a hexagon and a disc hold exactly the lattice nodes inside
// them, about area / dx^2 per layer), a short run of a hexagonal duct with a polygon inlet and outlet (mass
// balance, created and removed counts, 1 and 2 threads and a checkpoint restart bitwise), bad input refused
// naming the zone and the key; and (validation binary, VARSPH_PIPE_VALIDATION) a circular pipe with a disc inlet
// carrying the Hagen-Poiseuille profile and an outlet: the profile against u = 2 U (1 - r^2 / R^2) and the
// pressure gradient against -8 mu U / R^2 (e.g. White, Viscous Fluid Flow, sec. 3-3).
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "io/checkpoint.hpp"
#include "scene/scene.hpp"
#include "sim/open_boundaries.hpp"
#include "sim/restart.hpp"
#include "sim/simulation.hpp"
#include "test_support.hpp"

using namespace varsph;

namespace {

constexpr double kPi = 3.14159265358979323846;
using P2 = std::array<double, 2>;

[[maybe_unused]] nlohmann::json poly_json(const std::vector<P2>& v) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : v) out.push_back({p[0], p[1]});
  return out;
}

// a convex polygon (counter-clockwise) holds (a, b) strictly: left of every edge (an independent inside test)
[[maybe_unused]] bool in_convex(const std::vector<P2>& v, double a, double b) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    const P2& p = v[i];
    const P2& q = v[(i + 1) % v.size()];
    if (!((q[0] - p[0]) * (b - p[1]) - (q[1] - p[1]) * (a - p[0]) > 0)) return false;
  }
  return true;
}

// the regular hexagon of circumradius r, flat sides at b = +-r sqrt(3)/2, counter-clockwise
[[maybe_unused]] std::vector<P2> hexagon(double r) {
  std::vector<P2> v;
  for (int k = 0; k < 6; ++k) v.push_back({r * std::cos(k * kPi / 3), r * std::sin(k * kPi / 3)});
  return v;
}

// A slab of fluid beyond a zone at x = 0 (direction +x, tangent +y, so the in-plane axes are a = y, b = z) on the
// lattice of the zone's bounding rectangle [lo, hi] in (a, b): `layers` planes x = (i + 1/2) dx, no walls. With an
// inlet of the given interface (keys), enough to build the zone (Simulation's setup).
[[maybe_unused]] nlohmann::json slab_json(double dx, P2 lo, P2 hi, const nlohmann::json& shape, int layers = 3) {
  nlohmann::json fluid = nlohmann::json::array();
  const int na = int(std::ceil((hi[0] - lo[0]) / dx - 1e-9)), nb = int(std::ceil((hi[1] - lo[1]) / dx - 1e-9));
  for (int i = 0; i < layers; ++i)
    for (int a = 0; a < na; ++a)
      for (int b = 0; b < nb; ++b) fluid.push_back({(i + 0.5) * dx, lo[0] + (a + 0.5) * dx, lo[1] + (b + 0.5) * dx});
  nlohmann::json zone = {{"name", "in"}, {"kind", "inlet"}, {"center", {0.0, 0.0, 0.0}}, {"direction", {1.0, 0.0, 0.0}},
                         {"tangent", {0.0, 1.0, 0.0}}, {"depth", 3 * dx}, {"velocity", {{"profile", "uniform"}, {"value", 1.0}}}};
  for (auto it = shape.begin(); it != shape.end(); ++it) zone[it.key()] = it.value();
  return {{"name", "slab"}, {"setup", "paper"}, {"dimension", 3},
          {"domain", {{"min", {-1.0, -1.0, -1.0}}, {"max", {1.0, 1.0, 1.0}}}},
          {"particles", {{"spacing", dx}}},
          {"kernel", {{"type", "wendland_c2"}, {"h_over_dx", 1.3}}},
          {"fluid", {{"rho0", 1000.0}, {"c0", 20.0}}},
          {"bodies", {{{"kind", "fluid"}, {"shape", "points"}, {"points", fluid}}}},
          {"open_boundaries", {zone}},
          {"physics", {{"density", "continuity"}, {"laminar_viscosity", {{"nu", 0.01}}}}},
          {"integrator", {{"type", "symplectic_euler"}, {"dt", 0.002}}},
          {"time", {{"end", 1.0}}}};
}

// the buffer particles' in-plane points (a, b) = (y, z) of zone 0, and their layers
[[maybe_unused]] std::vector<P2> buffer_points(Simulation<3>& sim, int zone_index = 0) {
  const auto& zone = sim.store().get<std::int32_t>("open_zone");
  std::vector<P2> out;
  for (std::size_t i = 0; i < sim.size(); ++i)
    if (zone[i] == zone_index) out.push_back({double(sim.fields().x[i][1]), double(sim.fields().x[i][2])});
  return out;
}

[[maybe_unused]] std::vector<std::byte> field_bytes(const Simulation<3>& sim) {
  std::vector<std::byte> out;
  static const std::set<std::string> state = {"position", "velocity", "density", "pressure", "mass", "id", "kind", "open_zone"};
  for (const auto& f : sim.store().fields()) {
    if (!state.count(f->name())) continue;
    const auto* p = static_cast<const std::byte*>(f->raw());
    out.insert(out.end(), p, p + f->bytes_per_particle() * sim.size());
  }
  return out;
}

[[maybe_unused]] std::string input_error(const nlohmann::json& j, const char* file = "poly.json") {
  try {
    const scene::Scene s = scene::parse_scene_json(j, file, {});
    if (s.dimension == 3) Simulation<3> sim(s);
    else Simulation<2> sim(s);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A duct along x whose cross-section (y, z) is `section` (a convex polygon, counter-clockwise): fluid on the lattice
// of its bounding rectangle for 0 < x < L, walls of `wall_layers` on the same lattice outside it (nodes within
// wall_layers spacings of the section: the polygon offset outward), over the zones too; an inlet at x = 0 and an
// outlet at x = L, both `polygon` zones of the section, depth 3 dx (Wendland C2, h/dx 1.3: support 2.6 dx). The
// outlet's tangent is -y, so that its second in-plane axis (direction x tangent) is +z as the inlet's: the zones'
// lattices (from their bounding rectangles' lower corners) are then the fluid's.
struct Duct {
  double dx, L;
  std::vector<P2> section;
  P2 lo, hi;
};

[[maybe_unused]] bool in_offset(const std::vector<P2>& v, double a, double b, double off) {  // inside the polygon pushed out by off
  for (std::size_t i = 0; i < v.size(); ++i) {
    const P2& p = v[i];
    const P2& q = v[(i + 1) % v.size()];
    const double ex = q[0] - p[0], ey = q[1] - p[1], len = std::hypot(ex, ey);
    if (!((ex * (b - p[1]) - ey * (a - p[0])) / len > -off)) return false;
  }
  return true;
}

[[maybe_unused]] nlohmann::json duct_json(const Duct& d, double u) {
  nlohmann::json fluid = nlohmann::json::array(), vel = nlohmann::json::array(), wall = nlohmann::json::array();
  const int layers = 3;
  const int na = int(std::ceil((d.hi[0] - d.lo[0]) / d.dx - 1e-9)), nb = int(std::ceil((d.hi[1] - d.lo[1]) / d.dx - 1e-9));
  const int nx = int(std::lround(d.L / d.dx));
  for (int i = -layers; i < nx + layers; ++i)
    for (int a = -layers - 1; a < na + layers + 1; ++a)
      for (int b = -layers - 1; b < nb + layers + 1; ++b) {
        const double x = (i + 0.5) * d.dx, y = d.lo[0] + (a + 0.5) * d.dx, z = d.lo[1] + (b + 0.5) * d.dx;
        if (in_convex(d.section, y, z)) {
          if (i >= 0 && i < nx) {
            fluid.push_back({x, y, z});
            vel.push_back({u, 0.0, 0.0});
          }
        } else if (in_offset(d.section, y, z, layers * d.dx)) {
          wall.push_back({x, y, z});
        }
      }
  const double m = 0.2;
  return {{"name", "duct"}, {"setup", "paper"}, {"dimension", 3},
          {"domain", {{"min", {-layers * d.dx - m, d.lo[0] - layers * d.dx - m, d.lo[1] - layers * d.dx - m}},
                      {"max", {d.L + layers * d.dx + m, d.hi[0] + layers * d.dx + m, d.hi[1] + layers * d.dx + m}}}},
          {"particles", {{"spacing", d.dx}}},
          {"kernel", {{"type", "wendland_c2"}, {"h_over_dx", 1.3}}},
          {"fluid", {{"rho0", 1000.0}, {"c0", 20.0}}},
          {"bodies", {{{"kind", "fluid"}, {"shape", "points"}, {"points", fluid}, {"velocities", vel}},
                      {{"kind", "boundary"}, {"shape", "points"}, {"points", wall}}}},
          {"open_boundaries",
           {{{"name", "in"}, {"kind", "inlet"}, {"center", {0.0, 0.0, 0.0}}, {"direction", {1.0, 0.0, 0.0}},
             {"tangent", {0.0, 1.0, 0.0}}, {"depth", layers * d.dx}, {"polygon", poly_json(d.section)},
             {"velocity", {{"profile", "uniform"}, {"value", u}}}},
            {{"name", "out"}, {"kind", "outlet"}, {"center", {d.L, 0.0, 0.0}}, {"direction", {-1.0, 0.0, 0.0}},
             {"tangent", {0.0, -1.0, 0.0}}, {"depth", layers * d.dx}, {"polygon", poly_json(d.section)}, {"pressure", 0.0}}}},
          {"physics", {{"density", "continuity"}, {"laminar_viscosity", {{"nu", 0.01}}}}},
          {"boundary", {{"model", "dummy_adami"}, {"slip", "free_slip"}}},
          {"integrator", {{"type", "symplectic_euler"}, {"cfl", 0.2}}},
          {"time", {{"end", 1.0}}}};
}

// the hexagonal duct of the fast tests: circumradius 0.25 m, dx 0.05 m (about 70 nodes a layer), 0.5 m long
[[maybe_unused]] Duct hex_duct() {
  const double r = 0.25;
  return {0.05, 0.5, hexagon(r), {-r, -r * std::sqrt(3.0) / 2}, {r, r * std::sqrt(3.0) / 2}};
}

[[maybe_unused]] scene::Scene hex_scene(const std::vector<std::string>& sets = {}) {
  return scene::parse_scene_json(duct_json(hex_duct(), 1.0), "hex_duct.json", sets);
}

}  // namespace

#ifndef VARSPH_PIPE_VALIDATION

// A square polygon with the rectangle's corners is the rectangle zone: the same lattice (positions bit for bit, in
// the same order), and then the same run bit for bit (30 steps of a tilted 3D inflow).
TEST(OpenPolygon, SquarePolygonIsTheRectangleZoneBitwise) {
  const double dx = 0.1;
  nlohmann::json rect = slab_json(dx, {-0.3, -0.2}, {0.3, 0.2}, {{"width", {0.6, 0.4}}});
  nlohmann::json poly = slab_json(dx, {-0.3, -0.2}, {0.3, 0.2},
                                  {{"polygon", poly_json({{-0.3, -0.2}, {0.3, -0.2}, {0.3, 0.2}, {-0.3, 0.2}})}});
  Simulation<3> a(scene::parse_scene_json(rect, "rect.json", {}));
  Simulation<3> b(scene::parse_scene_json(poly, "poly.json", {}));
  EXPECT_EQ(buffer_points(a).size(), 3u * 6u * 4u);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(field_bytes(a) == field_bytes(b));
  for (int s = 0; s < 30; ++s) a.advance(), b.advance();
  EXPECT_GT(a.flow().created, 0);
  EXPECT_EQ(a.flow().created, b.flow().created);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(field_bytes(a) == field_bytes(b));
}

// A triangle, a hexagon and a disc hold exactly the nodes of their bounding rectangle's lattice that lie inside
// them (checked against an independent test: left of every edge of the convex polygon, r < R for the disc), in
// every layer, and their count per layer is the area / dx^2 to within the boundary's share: measured (dx 0.02)
// triangle 788 nodes for 787.5 (+0.06 %), hexagon (circumradius 0.45 m) 1317 for 1315.3 (+0.13 %), disc (R = 0.5 m)
// 1976 for 1963.5 (+0.64 %); bound 2 % (a smaller hexagon, circumradius 0.25 m, gave +1.49 %).
TEST(OpenPolygon, TriangleHexagonAndDiscHoldTheirInsideNodes) {
  const double dx = 0.02;
  struct Case {
    const char* name;
    std::vector<P2> poly;  // empty: the disc
    double area;
  };
  const double R = 0.5;
  const std::vector<P2> tri = {{-0.45, -0.3}, {0.5, -0.2}, {-0.1, 0.4}};
  const double tri_area = 0.5 * std::abs((tri[1][0] - tri[0][0]) * (tri[2][1] - tri[0][1]) - (tri[2][0] - tri[0][0]) * (tri[1][1] - tri[0][1]));
  const std::vector<Case> cases = {{"triangle", tri, tri_area},
                                   {"hexagon", hexagon(0.45), 1.5 * std::sqrt(3.0) * 0.45 * 0.45},
                                   {"disc", {}, kPi * R * R}};
  for (const Case& c : cases) {
    P2 lo{1e9, 1e9}, hi{-1e9, -1e9};
    nlohmann::json shape;
    if (c.poly.empty()) {
      lo = {-R, -R}, hi = {R, R};
      shape = {{"radius", R}};
    } else {
      for (const auto& p : c.poly)
        for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
      // a clockwise copy of the triangle: either orientation is accepted
      std::vector<P2> v = c.poly;
      if (std::string(c.name) == "triangle") std::reverse(v.begin(), v.end());
      shape = {{"polygon", poly_json(v)}};
    }
    Simulation<3> sim(scene::parse_scene_json(slab_json(dx, lo, hi, shape), "slab.json", {}));
    const std::vector<P2> got = buffer_points(sim);
    const int na = int(std::ceil((hi[0] - lo[0]) / dx - 1e-9)), nb = int(std::ceil((hi[1] - lo[1]) / dx - 1e-9));
    std::size_t expected = 0;
    for (int a = 0; a < na; ++a)
      for (int b = 0; b < nb; ++b) {
        const double pa = lo[0] + (a + 0.5) * dx, pb = lo[1] + (b + 0.5) * dx;
        expected += c.poly.empty() ? pa * pa + pb * pb < R * R : in_convex(c.poly, pa, pb);
      }
    EXPECT_EQ(got.size(), 3 * expected) << c.name;
    for (const P2& p : got) {
      const bool in = c.poly.empty() ? p[0] * p[0] + p[1] * p[1] < R * R : in_convex(c.poly, p[0], p[1]);
      EXPECT_TRUE(in) << c.name << " (" << p[0] << ", " << p[1] << ")";
      const double ja = (p[0] - lo[0]) / dx - 0.5, jb = (p[1] - lo[1]) / dx - 0.5;
      EXPECT_NEAR(ja, std::round(ja), 1e-9);
      EXPECT_NEAR(jb, std::round(jb), 1e-9);
    }
    const double per_layer = double(got.size()) / 3, ideal = c.area / (dx * dx);
    std::printf("%s: %.0f nodes a layer for area / dx^2 = %.1f (%+.2f %%)\n", c.name, per_layer, ideal, 100 * (per_layer / ideal - 1));
    EXPECT_NEAR(per_layer / ideal, 1.0, 0.02) << c.name;
  }
}

// A hexagonal duct with a polygon inlet (uniform 1 m/s) and a polygon outlet (p = 0), the fluid moving at the
// inflow speed from the start: 300 steps create and remove whole layers, every column of the inlet keeps its 3
// particles, and the mass balance closes to round-off.
TEST(OpenPolygon, HexagonalDuctFeedsAndDrains) {
  const scene::Scene s = hex_scene();
  Simulation<3> sim(s);
  const std::size_t inlet0 = buffer_points(sim, 0).size(), outlet0 = buffer_points(sim, 1).size();
  std::size_t per_layer = 0;
  const Duct d = hex_duct();
  for (int a = 0; a < 10; ++a)
    for (int b = 0; b < 9; ++b) per_layer += in_convex(d.section, d.lo[0] + (a + 0.5) * d.dx, d.lo[1] + (b + 0.5) * d.dx);
  EXPECT_EQ(inlet0, 3 * per_layer);
  EXPECT_EQ(outlet0, 3 * per_layer);
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < 300; ++k) sim.advance();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto& fl = sim.flow();
  std::printf("hexagonal duct: %zu particles (%zu a layer), 300 steps to t = %.3f s in %.1f s: created %ld, removed %ld, "
              "mass balance %.3g of M0\n", sim.size(), per_layer, sim.time(), wall, fl.created, fl.removed_outlet,
              std::abs(fl.mass_in - fl.mass_out() - (sim.fluid_mass() - fl.mass0)) / fl.mass0);
  EXPECT_GE(fl.created, long(2 * per_layer));  // at 1 m/s about t / dx layers
  EXPECT_GE(fl.removed_outlet, long(2 * per_layer));
  EXPECT_LE(std::abs(fl.mass_in - fl.mass_out() - (sim.fluid_mass() - fl.mass0)), 1e-12 * fl.mass0);
  EXPECT_EQ(buffer_points(sim, 0).size(), inlet0);
  // the fluid between the zones still fills the duct at about the inflow speed
  double ux = 0, n = 0;
  const auto& zone = sim.store().get<std::int32_t>("open_zone");
  for (std::size_t i = 0; i < sim.size(); ++i)
    if (sim.fields().kind[i] == 0 && zone[i] < 0) ux += double(sim.fields().v[i][0]), n += 1;
  EXPECT_NEAR(ux / n, 1.0, 0.1);
  EXPECT_NEAR(n / double(per_layer), d.L / d.dx, 1.0);
}

TEST(OpenPolygon, ThreadsGiveTheSameBits) {
  const int before = omp_get_max_threads();
  std::vector<std::byte> a, b;
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    Simulation<3> sim(hex_scene());
    for (int s = 0; s < 150; ++s) sim.advance();
    EXPECT_GT(sim.flow().created, 0);
    EXPECT_GT(sim.flow().removed_outlet, 0);
    (threads == 1 ? a : b) = field_bytes(sim);
  }
  omp_set_num_threads(before);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(a == b);
}

TEST(OpenPolygon, RestartFromACheckpointIsBitwise) {
  const auto dir = test::scratch_dir("open_polygon_restart");
  const auto path = dir / "step.h5";
  Simulation<3> a(hex_scene());
  for (int s = 0; s < 80; ++s) a.advance();
  EXPECT_GT(a.flow().created, 0);
  io::write_checkpoint(path, checkpoint_header(a, nlohmann::json::object()), a.store());
  for (int s = 0; s < 80; ++s) a.advance();
  Simulation<3> b(hex_scene());
  restore_from_checkpoint(b, io::read_checkpoint(path), path.string());
  for (int s = 0; s < 80; ++s) b.advance();
  EXPECT_EQ(a.next_id(), b.next_id());
  EXPECT_EQ(a.flow().created, b.flow().created);
  EXPECT_EQ(a.flow().removed_outlet, b.flow().removed_outlet);
  EXPECT_EQ(a.flow().mass_in, b.flow().mass_in);
  EXPECT_EQ(a.time(), b.time());
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(field_bytes(a) == field_bytes(b));
}

TEST(OpenPolygon, BadInputStopsBeforeTheRunNamingZoneAndKey) {
  const auto expect = [](const nlohmann::json& j, const std::string& key, const std::string& what) {
    const std::string e = input_error(j);
    EXPECT_NE(e.find("poly.json"), std::string::npos) << e;
    EXPECT_NE(e.find(key), std::string::npos) << e;
    EXPECT_NE(e.find(what), std::string::npos) << e;
  };
  const Duct d = hex_duct();
  const std::string key = "key 'open_boundaries.0.polygon' (zone 'in')";
  nlohmann::json j = duct_json(d, 1.0);
  j["open_boundaries"][0]["polygon"] = poly_json({{0.0, 0.0}, {0.1, 0.0}});
  expect(j, key, "at least 3 vertices");
  j["open_boundaries"][0]["polygon"] = poly_json({{-0.1, -0.1}, {0.0, 0.0}, {0.1, 0.1}});
  expect(j, key, "non-zero area");
  j["open_boundaries"][0]["polygon"] = poly_json({{-0.1, -0.1}, {0.1, 0.1}, {0.1, -0.1}, {-0.1, 0.2}});  // a bow tie
  expect(j, key, "intersects itself");
  j["open_boundaries"][0]["polygon"] = poly_json({{-0.1, -0.1}, {0.1, -0.1}, {0.1, 0.1}, {0.0, -0.1}});  // folds back on an edge
  expect(j, key, "intersects itself");
  j["open_boundaries"][0]["polygon"] = poly_json({{-0.1, -0.1}, {0.1, -0.1}, {0.1, 5.0}});
  expect(j, key, "inside domain");
  j["open_boundaries"][0]["polygon"] = poly_json({{-0.1, -0.1}, {0.1, -0.1}, {0.1, 0.1}, {-0.1, 0.1}});
  j["open_boundaries"][0]["width"] = {0.2, 0.2};
  expect(j, key, "one interface shape");
  j = duct_json(d, 1.0);
  j["open_boundaries"][0]["polygon"] = poly_json({{-0.4, -0.1}, {0.4, -0.1}, {0.0, 0.2}});  // reaches into the walls
  expect(j, key, "overlaps a wall");
  j = duct_json(d, 1.0);
  j["open_boundaries"][0]["velocity"] = {{"profile", "parabolic"}, {"peak", 1.0}};  // no pipe profile on a polygon
  expect(j, "key 'open_boundaries.0.velocity.profile' (zone 'in')", "disc");
  j = duct_json(d, 1.0);
  j["open_boundaries"][0].erase("polygon");
  j["open_boundaries"][0]["radius"] = -0.1;
  expect(j, "key 'open_boundaries.0.radius' (zone 'in')", "");
  // 2D: the interface is a segment
  nlohmann::json j2 = {
      {"name", "flat"}, {"setup", "paper"}, {"dimension", 2},
      {"domain", {{"min", {-1.0, -1.0}}, {"max", {1.0, 1.0}}}},
      {"particles", {{"spacing", 0.1}}},
      {"fluid", {{"rho0", 1000.0}, {"c0", 20.0}}},
      {"bodies", {{{"kind", "fluid"}, {"shape", "box"}, {"min", {0.0, 0.0}}, {"max", {0.5, 0.5}}}}},
      {"open_boundaries",
       {{{"name", "in"}, {"kind", "inlet"}, {"center", {0.0, 0.25}}, {"direction", {1.0, 0.0}}, {"depth", 0.4},
         {"polygon", poly_json({{-0.2, -0.2}, {0.2, -0.2}, {0.0, 0.2}})}, {"velocity", {{"value", 1.0}}}}}},
      {"integrator", {{"type", "symplectic_euler"}, {"dt", 0.002}}},
      {"time", {{"end", 1.0}}}};
  expect(j2, key, "no `polygon` in 2D");
  j2["open_boundaries"][0].erase("polygon");
  j2["open_boundaries"][0]["radius"] = 0.2;
  expect(j2, "key 'open_boundaries.0.radius' (zone 'in')", "no `radius` in 2D");
  // the duct as given is accepted
  EXPECT_EQ(input_error(duct_json(d, 1.0)), "");
}

#else  // VARSPH_PIPE_VALIDATION

// Hagen-Poiseuille flow in a circular pipe (radius R = 0.5 m, L = 1.5 m, nu = 1 m^2/s, rho0 = 1000, c0 = 20 m/s,
// mean speed U = 0.1 m/s, Re = 2 U R / nu = 0.1) with a disc inlet carrying u = 2 U (1 - r^2 / R^2) and an outlet
// at p = 0; walls: lattice nodes within 4 spacings outside the pipe (dummy_adami, no slip); Wendland C2, h/dx 1.6,
// Verlet CFL 0.2, R/dx 6 (pipelines/open/pipe_3d.json, make_pipe_3d.py). Against the exact u(r) = 2 U (1 - r^2/R^2)
// (the fluid in the middle third in rings of one spacing: the largest |mean(u_i - u(r_i))| / u_max) and dp/dx =
// -8 mu U / R^2 = -3200 Pa/m (least squares over 0.3 <= x <= 1.2 m) at t = 1 s (four viscous times R^2 / nu).
// Measured 2026-11-28 (1 thread, load 6-8): profile 3.52 % of u_max, dp/dx -3119.2 Pa/m (-2.52 %), 757 steps,
// 34 s. The fluid near the wall moves faster than the exact profile and the centre slower (the staircase of the
// lattice wall, docs/validation.md section 19); h/dx 1.3 gave 4.2 % and -6.2 %, R/dx 8 at h/dx 1.6 6.2 % and -10 %:
// the error does not fall with dx at these resolutions. Bounds: 5 % and 4 %.
TEST(OpenPipe, HagenPoiseuilleProfileAndPressureDrop) {
  const double R = 0.5, L = 1.5, U = 0.1, nu = 1.0, rho0 = 1000;
  // R/dx 6, Wendland C2 at h/dx 1.6 (support 3.2 dx: 4 wall layers, zones 4 spacings deep)
  const double tend = 1.0, hdx = 1.6;
  for (const int per_r : {6}) {
    const double dx = R / per_r;
    // the pipe's fluid and walls on the lattice of the disc's bounding square (the disc zone's lattice)
    nlohmann::json fluid = nlohmann::json::array(), wall = nlohmann::json::array();
    const int layers = int(std::ceil(2 * hdx - 1e-9)), nx = int(std::lround(L / dx)), n = 2 * per_r;
    for (int i = -layers; i < nx + layers; ++i)
      for (int a = -layers; a < n + layers; ++a)
        for (int b = -layers; b < n + layers; ++b) {
          const double x = (i + 0.5) * dx, y = -R + (a + 0.5) * dx, z = -R + (b + 0.5) * dx, r = std::hypot(y, z);
          if (r < R) {
            if (i >= 0 && i < nx) fluid.push_back({x, y, z});
          } else if (r < R + layers * dx) {
            wall.push_back({x, y, z});
          }
        }
    const double m = 0.2, e = R + layers * dx + m;
    nlohmann::json j = {
        {"name", "pipe_3d"}, {"setup", "paper"}, {"dimension", 3},
        {"domain", {{"min", {-layers * dx - m, -e, -e}}, {"max", {L + layers * dx + m, e, e}}}},
        {"particles", {{"spacing", dx}}},
        {"kernel", {{"type", "wendland_c2"}, {"h_over_dx", hdx}}},
        {"fluid", {{"rho0", rho0}, {"c0", 20.0}}},
        {"bodies", {{{"kind", "fluid"}, {"shape", "points"}, {"points", fluid}},
                    {{"kind", "boundary"}, {"shape", "points"}, {"points", wall}}}},
        {"open_boundaries",
         {{{"name", "inlet"}, {"kind", "inlet"}, {"center", {0.0, 0.0, 0.0}}, {"direction", {1.0, 0.0, 0.0}},
           {"tangent", {0.0, 1.0, 0.0}}, {"depth", layers * dx}, {"radius", R},
           {"velocity", {{"profile", "parabolic"}, {"peak", 2 * U}}}},
          {{"name", "outlet"}, {"kind", "outlet"}, {"center", {L, 0.0, 0.0}}, {"direction", {-1.0, 0.0, 0.0}},
           {"tangent", {0.0, 1.0, 0.0}}, {"depth", layers * dx}, {"radius", R}, {"pressure", 0.0}}}},
        {"physics", {{"density", "continuity"}, {"laminar_viscosity", {{"nu", nu}}}}},
        {"boundary", {{"model", "dummy_adami"}, {"slip", "no_slip"}}},
        {"integrator", {{"type", "verlet"}, {"cfl", 0.2}}},
        {"time", {{"end", tend}}}};
    const scene::Scene s = scene::parse_scene_json(j, "pipe_3d.json", {});
    Simulation<3> sim(s);
    const auto t0 = std::chrono::steady_clock::now();
    while (sim.time() < s.t_end - 0.5 * sim.dt()) sim.advance();
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& f = sim.fields();
    const auto& zone = sim.store().get<std::int32_t>("open_zone");
    std::vector<double> su(std::size_t(per_r), 0.0), se(std::size_t(per_r), 0.0), cnt(std::size_t(per_r), 0.0);
    double sx = 0, sp = 0, sxx = 0, sxp = 0, np = 0, cross = 0;
    for (std::size_t i = 0; i < sim.size(); ++i) {
      if (f.kind[i] != 0 || zone[i] >= 0) continue;
      const double x = f.x[i][0], r = std::hypot(double(f.x[i][1]), double(f.x[i][2]));
      if (x >= L / 3 && x <= 2 * L / 3) {
        const std::size_t k = std::size_t(std::clamp(int(r / dx), 0, per_r - 1));
        su[k] += f.v[i][0];
        se[k] += 2 * U * (1 - std::min(1.0, r * r / (R * R)));
        cnt[k] += 1;
        cross = std::max(cross, std::hypot(double(f.v[i][1]), double(f.v[i][2])));
      }
      if (x >= 0.3 && x <= L - 0.3) sx += x, sp += f.p[i], sxx += x * x, sxp += x * f.p[i], np += 1;
    }
    double profile = 0;
    for (std::size_t k = 0; k < su.size(); ++k)
      if (cnt[k] > 0) {
        profile = std::max(profile, std::abs(su[k] - se[k]) / cnt[k] / (2 * U));
        std::printf("  r in [%.3f, %.3f): %3.0f particles, u %.5f, exact %.5f m/s\n", double(k) * dx, double(k + 1) * dx, cnt[k],
                    su[k] / cnt[k], se[k] / cnt[k]);
      }
    const double dpdx = (np * sxp - sx * sp) / (np * sxx - sx * sx), exact = -8 * rho0 * nu * U / (R * R);
    const auto& fl = sim.flow();
    const double balance = std::abs(fl.mass_in - fl.mass_out() - (sim.fluid_mass() - fl.mass0)) / fl.mass0;
    std::printf("pipe R/dx %d: %zu particles, %ld steps to t = %.3f s in %.1f s (%.1f ms/step, 1 thread): profile %.3f %% of "
                "u_max, dp/dx %.1f Pa/m (exact %.1f, %+.2f %%), cross-flow %.2e of u_max, created %ld, removed %ld, "
                "mass balance %.3g of M0\n", per_r, sim.size(), sim.step(), sim.time(), wall_s, 1e3 * wall_s / double(sim.step()),
                100 * profile, dpdx, exact, 100 * (dpdx / exact - 1), cross / (2 * U), fl.created, fl.removed_outlet, balance);
    EXPECT_LT(balance, 1e-12);
    EXPECT_GT(fl.created, 0);
    EXPECT_GT(fl.removed_outlet, 0);
    EXPECT_LT(profile, 0.05);
    EXPECT_LT(std::abs(dpdx / exact - 1), 0.04);
  }
}

#endif  // VARSPH_PIPE_VALIDATION
