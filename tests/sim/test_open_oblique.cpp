// Oblique plane open-boundary zones (issue 32; sim/open_boundaries.hpp, docs/open_boundaries.md "Oblique
// zones"): plane Poiseuille flow through a channel inclined at 30 degrees with an oblique inlet and outlet,
// against u = 6 U y (H - y) / H^2 across the channel (e.g. White, Viscous Fluid Flow, sec. 3-2) and against the
// same flow rotated to the axis; mass balance, created and removed counts, threads and a restart bitwise; a 3D
// oblique zone's lattice; bad input refused naming the zone and the key.
//
// The channel is the one of pipelines/open/channel_poiseuille.json (H = 1 m, L = 1.5 m, nu = 1 m^2/s, dx 0.05,
// Gaussian h = 1.2 dx, Verlet, dummy walls with no slip, inlet parabolic with peak 0.15 m/s, outlet p = 0),
// rotated: its fluid and walls are `points` bodies on the rotated lattice, so every particle of the inclined
// run is the image of one of the axis-aligned run (pipelines/open/inclined_channel.json is this scene at 30 deg,
// written by pipelines/open/make_inclined_channel.py).
#include <gtest/gtest.h>

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include <Eigen/Geometry>
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
constexpr double kH = 1.0, kL = 1.5, kU = 0.1;
// the fast tier runs the channel at dx 0.1 (10 rows, about 200 particles: seconds); the validation binary
// (VARSPH_OBLIQUE_VALIDATION) at the dx 0.05 of channel_poiseuille.json (20 rows, about 1 100, minutes)
#ifdef VARSPH_OBLIQUE_VALIDATION
constexpr double kDx = 0.05;
#else
constexpr double kDx = 0.1;
#endif
constexpr int kRows = int(kH / kDx + 0.5), kCols = int(kL / kDx + 0.5), kLayers = 4;

// e_s (along the channel) and e_n (across) at angle theta [deg]
struct Frame {
  double c, s;
  explicit Frame(double deg) : c(std::cos(deg * kPi / 180)), s(std::sin(deg * kPi / 180)) {}
  std::vector<double> at(double along, double across) const { return {along * c - across * s, along * s + across * c}; }
  double along(const Vec<2>& x) const { return double(x[0]) * c + double(x[1]) * s; }
  double across(const Vec<2>& x) const { return -double(x[0]) * s + double(x[1]) * c; }
};

// The channel at angle theta: fluid 30 x 20 lattice points, walls 4 layers on both sides over the zones' length
// too, an oblique inlet (depth 0.2 m = 4 spacings, the Gaussian support is 3.6) and outlet.
nlohmann::json inclined_json(double deg, double t_end = 2.0) {
  const Frame F(deg);
  nlohmann::json fluid = nlohmann::json::array(), wall = nlohmann::json::array();
  double lo[2] = {1e9, 1e9}, hi[2] = {-1e9, -1e9};
  for (int i = -kLayers; i < kCols + kLayers; ++i)
    for (int j = -kLayers; j < kRows + kLayers; ++j) {
      const bool in_fluid = i >= 0 && i < kCols && j >= 0 && j < kRows, in_wall = j < 0 || j >= kRows;
      if (!in_fluid && !in_wall) continue;
      const auto p = F.at((i + 0.5) * kDx, (j + 0.5) * kDx);
      (in_fluid ? fluid : wall).push_back(p);
      for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], p[std::size_t(a)]), hi[a] = std::max(hi[a], p[std::size_t(a)]);
    }
  nlohmann::json j = {
      {"name", "inclined_channel"}, {"setup", "paper"}, {"dimension", 2},
      {"domain", {{"min", {lo[0] - 0.2, lo[1] - 0.2}}, {"max", {hi[0] + 0.2, hi[1] + 0.2}}}},
      {"particles", {{"spacing", kDx}}},
      {"kernel", {{"type", "gaussian"}, {"h_over_dx", 1.2}}},
      {"fluid", {{"rho0", 1000.0}, {"c0", 20.0}}},
      {"bodies", {{{"kind", "fluid"}, {"shape", "points"}, {"points", fluid}},
                  {{"kind", "boundary"}, {"shape", "points"}, {"points", wall}}}},
      {"open_boundaries",
       {{{"name", "inlet"}, {"kind", "inlet"}, {"center", F.at(0, 0.5 * kH)}, {"direction", F.at(1, 0)},
         {"depth", kLayers * kDx}, {"width", kH}, {"velocity", {{"profile", "parabolic"}, {"peak", 1.5 * kU}}}},
        {{"name", "outlet"}, {"kind", "outlet"}, {"center", F.at(kL, 0.5 * kH)}, {"direction", F.at(-1, 0)},
         {"depth", kLayers * kDx}, {"width", kH}, {"pressure", 0.0}}}},
      {"physics", {{"density", "continuity"}, {"laminar_viscosity", {{"nu", 1.0}}}}},
      {"boundary", {{"model", "dummy_adami"}, {"slip", "no_slip"}}},
      {"integrator", {{"type", "verlet"}, {"cfl", 0.2}}},
      {"time", {{"end", t_end}}}};
  return j;
}

scene::Scene inclined(double deg, const std::vector<std::string>& sets = {}, double t_end = 2.0) {
  return scene::parse_scene_json(inclined_json(deg, t_end), "inclined_channel.json", sets);
}

[[maybe_unused]] std::string input_error(const nlohmann::json& j) {
  try {
    const scene::Scene s = scene::parse_scene_json(j, "inclined_channel.json", {});
    Simulation<2> sim(s);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The figures of docs/validation.md section 19 in the channel's own frame: profile = the largest difference,
// over the 20 rows, of the mean along-channel speed of the fluid in the middle third from u(y_row), over
// u_max = 1.5 U; dp/ds = least-squares slope of p over the fluid with 0.3 <= s <= 1.2 m; the largest row mean
// of the cross-channel speed over u_max; the mass balance over M0.
struct Measured {
  double profile = 0, dpds = 0, cross = 0, balance = 0;
  long created = 0, removed = 0;
};

Measured measure(Simulation<2>& sim, double deg) {
  const Frame F(deg);
  const auto& f = sim.fields();
  const auto& zone = sim.store().get<std::int32_t>("open_zone");
  std::vector<double> su(kRows, 0.0), sv(kRows, 0.0), cnt(kRows, 0.0);
  double sx = 0, sp = 0, sxx = 0, sxp = 0, n = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.kind[i] != 0 || zone[i] >= 0) continue;
    const double s = F.along(f.x[i]), y = F.across(f.x[i]);
    if (s >= kL / 3 && s <= 2 * kL / 3) {
      const std::size_t r = std::size_t(std::clamp(int(std::floor(y / kDx)), 0, kRows - 1));
      su[r] += F.along(f.v[i]);
      sv[r] += F.across(f.v[i]);
      cnt[r] += 1;
    }
    if (s >= 0.3 && s <= kL - 0.3) {
      const double p = f.p[i];
      sx += s, sp += p, sxx += s * s, sxp += s * p, n += 1;
    }
  }
  Measured m;
  const double umax = 1.5 * kU;
  for (std::size_t r = 0; r < std::size_t(kRows); ++r) {
    if (cnt[r] == 0) continue;
    const double y = (double(r) + 0.5) * kDx;
    m.profile = std::max(m.profile, std::abs(su[r] / cnt[r] - 6 * kU * y * (kH - y) / (kH * kH)) / umax);
    m.cross = std::max(m.cross, std::abs(sv[r] / cnt[r]) / umax);
  }
  m.dpds = (n * sxp - sx * sp) / (n * sxx - sx * sx);
  const auto& fl = sim.flow();
  m.balance = std::abs(fl.mass_in - fl.mass_out() - (sim.fluid_mass() - fl.mass0)) / fl.mass0;
  m.created = fl.created;
  m.removed = fl.removed_outlet;
  return m;
}

Measured run_to_end(double deg) {
  const scene::Scene s = inclined(deg);
  Simulation<2> sim(s);
  while (sim.time() < s.t_end - 0.5 * sim.dt()) sim.advance();
  const Measured m = measure(sim, deg);
  std::printf("inclined channel %g deg, dx %g, t = %.3g s (%ld steps): profile %.4f %% of u_max, dp/ds %.3f Pa/m (exact -1200), "
              "cross-channel speed %.2e of u_max, mass balance %.3g of M0, created %ld, removed %ld\n",
              deg, kDx, sim.time(), sim.step(), 100 * m.profile, m.dpds, m.cross, m.balance, m.created, m.removed);
  return m;
}

[[maybe_unused]] std::vector<std::byte> field_bytes(const Simulation<2>& sim) {
  std::vector<std::byte> out;
  static const std::set<std::string> state = {"position", "velocity", "density", "pressure", "mass", "id", "kind", "open_zone"};
  for (const auto& f : sim.store().fields()) {
    if (!state.count(f->name())) continue;
    const auto* p = static_cast<const std::byte*>(f->raw());
    out.insert(out.end(), p, p + f->bytes_per_particle() * sim.size());
  }
  return out;
}

}  // namespace

TEST(OpenOblique, ZonesGetLatticesOnPlanesParallelToTheInterface) {
  const Frame F(30);
  Simulation<2> sim(inclined(30));
  const auto& f = sim.fields();
  const auto& zone = sim.store().get<std::int32_t>("open_zone");
  std::size_t count[2] = {0, 0};
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (zone[i] < 0) continue;
    ++count[zone[i]];
    // every buffer particle on the channel's rotated lattice: along and across at (k + 1/2) dx
    const double s = F.along(f.x[i]) / kDx - 0.5, y = F.across(f.x[i]) / kDx - 0.5;
    EXPECT_NEAR(s, std::round(s), 1e-9);
    EXPECT_NEAR(y, std::round(y), 1e-9);
    EXPECT_GE(y, -1e-9);
    EXPECT_LE(y, kRows - 1 + 1e-9);
    if (zone[i] == 0) {
      EXPECT_TRUE(s < 0 && s > -kLayers - 0.5) << s;
    } else {
      EXPECT_TRUE(s > kCols - 0.5 && s < kCols + kLayers) << s;
    }
    // the inflow along the normal: the parabola across the width, at rest on t = 0 only through no ramp
    if (zone[i] == 0) {
      const double yy = F.across(f.x[i]), u = 4 * 1.5 * kU * yy * (kH - yy) / (kH * kH);
      EXPECT_NEAR(F.along(f.v[i]), u, 1e-12);
      EXPECT_NEAR(F.across(f.v[i]), 0, 1e-12);
    }
  }
  EXPECT_EQ(count[0], std::size_t(kLayers * kRows));  // 4 layers x the rows
  EXPECT_EQ(count[1], std::size_t(kLayers * kRows));
  EXPECT_EQ(sim.count(0), std::size_t(kRows * kCols + 2 * kLayers * kRows));
  EXPECT_NEAR(sim.fluid_mass(), kRows * kCols * 1000.0 * kDx * kDx, 1e-9);
}

// The inclined flow against the analytic profile and against the same flow at 0 degrees (oblique keys with the
// direction on the axis): every particle of one run is the rotated image of one of the other, so only the
// round-off of the rotation (and its growth over the run) separates the figures; the counts are equal.
// Validation binary, dx 0.05 (docs/validation.md section 19, measured 2026-11-27): 30 deg profile 0.542 % of
// u_max, dp/ds -1194.06 Pa/m (0.50 %); 0 deg 0.529 %, -1196.11 (the box-zone scene channel_poiseuille.json:
// 0.53 %, -1196.1); 82 created / 80 removed in both. Goals: the 1 % and 2 %; rotated vs axis within
// 0.05 % of u_max and 0.5 % of dp/ds (measured 0.013 % and 0.17 %).
// Fast binary, dx 0.1 (10 rows, measured 2026-11-27): 30 deg profile 1.52 % of u_max, dp/ds -1147.3 Pa/m
// (4.4 %); 0 deg 1.49 %, -1143.3 (4.7 %); 22 created / 20 removed in both; rotated vs axis 0.028 % of u_max and
// 0.33 % of dp/ds. Bounds: 2 % and 6 % (the coarse resolution's error), the same figures within 0.1 % and 1 %.
TEST(OpenOblique, InclinedPoiseuilleMatchesTheProfileAndTheFlowOnTheAxis) {
  const Measured m30 = run_to_end(30), m0 = run_to_end(0);
  const double dpds_exact = -12 * 1000.0 * 1.0 * kU / (kH * kH);
#ifdef VARSPH_OBLIQUE_VALIDATION
  const double profile_goal = 0.01, dpds_goal = 0.02, same_profile = 5e-4, same_dpds = 5e-3;
#else
  const double profile_goal = 0.02, dpds_goal = 0.06, same_profile = 1e-3, same_dpds = 1e-2;
#endif
  EXPECT_LT(m30.profile, profile_goal);
  EXPECT_LT(std::abs(m30.dpds / dpds_exact - 1), dpds_goal);
  EXPECT_LT(m30.cross, 0.01);
  EXPECT_LT(m30.balance, 1e-12);
  EXPECT_GT(m30.created, 0);
  EXPECT_GT(m30.removed, 0);
  // rotated to the axis: the same figures
  EXPECT_EQ(m30.created, m0.created);
  EXPECT_EQ(m30.removed, m0.removed);
  EXPECT_NEAR(m30.profile, m0.profile, same_profile);
  EXPECT_NEAR(m30.dpds, m0.dpds, same_dpds * std::abs(dpds_exact));
  EXPECT_LT(m0.profile, profile_goal);
  EXPECT_LT(m0.balance, 1e-12);
}

#ifndef VARSPH_OBLIQUE_VALIDATION
TEST(OpenOblique, ThreadsGiveTheSameBits) {
  const int before = omp_get_max_threads();
  std::vector<std::byte> a, b;
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    Simulation<2> sim(inclined(30, {"open_boundaries.0.velocity.peak=1.5"}));  // 1 m/s mean: crossings soon
    for (int s = 0; s < 300; ++s) sim.advance();
    (threads == 1 ? a : b) = field_bytes(sim);
    EXPECT_GT(sim.flow().created, 20);
  }
  omp_set_num_threads(before);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(a == b);
}

TEST(OpenOblique, RestartFromACheckpointIsBitwise) {
  const auto dir = test::scratch_dir("open_oblique_restart");
  const auto path = dir / "step.h5";
  const std::vector<std::string> fast = {"open_boundaries.0.velocity.peak=1.5"};
  Simulation<2> a(inclined(30, fast));
  for (int s = 0; s < 150; ++s) a.advance();
  io::write_checkpoint(path, checkpoint_header(a, nlohmann::json::object()), a.store());
  for (int s = 0; s < 150; ++s) a.advance();
  Simulation<2> b(inclined(30, fast));
  restore_from_checkpoint(b, io::read_checkpoint(path), path.string());
  for (int s = 0; s < 150; ++s) b.advance();
  EXPECT_GT(a.flow().created, 0);
  EXPECT_EQ(a.next_id(), b.next_id());
  EXPECT_EQ(a.flow().created, b.flow().created);
  EXPECT_EQ(a.flow().removed_outlet, b.flow().removed_outlet);
  EXPECT_EQ(a.flow().mass_in, b.flow().mass_in);
  EXPECT_EQ(a.time(), b.time());
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(field_bytes(a) == field_bytes(b));
}

TEST(OpenOblique, BadInputStopsBeforeTheRunNamingZoneAndKey) {
  const Frame F(30);
  const auto expect = [](const nlohmann::json& j, const std::string& key, const std::string& what) {
    const std::string e = input_error(j);
    EXPECT_NE(e.find("inclined_channel.json"), std::string::npos) << e;
    EXPECT_NE(e.find(key), std::string::npos) << e;
    EXPECT_NE(e.find(what), std::string::npos) << e;
  };
  nlohmann::json j = inclined_json(30);
  j["open_boundaries"][0]["direction"] = {0.0, 0.0};
  expect(j, "key 'open_boundaries.0.direction' (zone 'inlet')", "non-zero");
  j = inclined_json(30);
  j["open_boundaries"][0]["depth"] = 3 * kDx;  // the Gaussian support is 3.6 spacings
  expect(j, "key 'open_boundaries.0.depth' (zone 'inlet')", "kernel support");
  j = inclined_json(30);
  j["open_boundaries"][0]["velocity"]["peak"] = -0.15;
  expect(j, "key 'open_boundaries.0.velocity.peak' (zone 'inlet')", "out of the domain");
  j = inclined_json(30);
  j["open_boundaries"][0]["direction"] = F.at(-1, 0);  // reversed: no fluid beyond the face
  expect(j, "key 'open_boundaries.0.direction' (zone 'inlet')", "point from the zone into the fluid");
  j = inclined_json(30);
  j["open_boundaries"][0]["width"] = 1.2;  // reaches into both walls
  expect(j, "key 'open_boundaries.0.center' (zone 'inlet')", "overlaps a wall");
  j = inclined_json(30);
  j["open_boundaries"][1]["center"] = F.at(0.1, 0.5);  // the outlet on top of the inlet
  j["open_boundaries"][1]["direction"] = F.at(1, 0);
  expect(j, "key 'open_boundaries.1.min' (zone 'outlet')", "does not overlap zone 'inlet'");
  j = inclined_json(30);
  j["open_boundaries"][0]["depth"] = 0.23;
  expect(j, "key 'open_boundaries.0.depth' (zone 'inlet')", "multiple of particles.spacing");
  j = inclined_json(30);
  j["open_boundaries"][0]["min"] = {0.0, 0.0};
  expect(j, "key 'open_boundaries.0.min' (zone 'inlet')", "not both");
  j = inclined_json(30);
  j["open_boundaries"][0]["tangent"] = {0.0, 1.0};
  expect(j, "key 'open_boundaries.0.tangent' (zone 'inlet')", "no tangent in 2D");
  j = inclined_json(30);
  j["open_boundaries"][0]["center"] = {-50.0, 0.0};
  expect(j, "key 'open_boundaries.0.center' (zone 'inlet')", "inside domain");
  // a zone that does not overlap (touching the fluid's far end, the outlet moved a spacing on) is accepted
  j = inclined_json(30);
  j["open_boundaries"][0]["direction"] = {2 * F.c, 2 * F.s};  // any length: normalised
  EXPECT_EQ(input_error(j), "");
}

// 3D: an oblique zone's lattice fills its rectangle on planes parallel to the interface, and a uniform inflow
// through it creates particles with the mass balance closed (a slab of fluid rotated about z and tilted, no walls)
TEST(OpenOblique, ThreeDimensionalZoneLatticeAndInflow) {
  const double dx = 0.1;
  const Eigen::Vector3d n = Eigen::Vector3d(std::cos(0.5), std::sin(0.5) * std::cos(0.3), std::sin(0.5) * std::sin(0.3));
  const Eigen::Vector3d t1 = Eigen::Vector3d::UnitZ().cross(n).normalized(), t2 = n.cross(t1);
  nlohmann::json fluid = nlohmann::json::array();
  for (int i = 0; i < 8; ++i)
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < 4; ++b) {
        const Eigen::Vector3d p = (i + 0.5) * dx * n + ((a + 0.5) * dx - 0.3) * t1 + ((b + 0.5) * dx - 0.2) * t2;
        fluid.push_back({p[0], p[1], p[2]});
      }
  nlohmann::json j = {
      {"name", "oblique_3d"}, {"setup", "paper"}, {"dimension", 3},
      {"domain", {{"min", {-1.5, -1.5, -1.5}}, {"max", {1.5, 1.5, 1.5}}}},
      {"particles", {{"spacing", dx}}},
      {"kernel", {{"type", "wendland_c2"}, {"h_over_dx", 1.3}}},
      {"fluid", {{"rho0", 1000.0}, {"c0", 20.0}}},
      {"bodies", {{{"kind", "fluid"}, {"shape", "points"}, {"points", fluid}}}},
      {"open_boundaries",
       {{{"name", "in"}, {"kind", "inlet"}, {"center", {0.0, 0.0, 0.0}}, {"direction", {n[0], n[1], n[2]}},
         {"tangent", {t1[0], t1[1], t1[2]}}, {"depth", 0.3}, {"width", {0.6, 0.4}},
         {"velocity", {{"profile", "uniform"}, {"value", 1.0}}}}}},
      {"physics", {{"density", "continuity"}, {"laminar_viscosity", {{"nu", 0.01}}}}},
      {"integrator", {{"type", "symplectic_euler"}, {"dt", 0.002}}},
      {"time", {{"end", 1.0}}}};
  Simulation<3> sim(scene::parse_scene_json(j, "oblique_3d.json", {}));
  const auto& f = sim.fields();
  const auto& zone = sim.store().get<std::int32_t>("open_zone");
  std::size_t buffers = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (zone[i] != 0) continue;
    ++buffers;
    const Eigen::Vector3d x = f.x[i].template cast<double>();
    const double k = x.dot(n) / dx + 0.5, a = (x.dot(t1) + 0.3) / dx - 0.5, b = (x.dot(t2) + 0.2) / dx - 0.5;
    EXPECT_NEAR(k, std::round(k), 1e-9);  // on the planes -(k + 1/2) dx from the interface
    EXPECT_NEAR(a, std::round(a), 1e-9);
    EXPECT_NEAR(b, std::round(b), 1e-9);
    EXPECT_NEAR((f.v[i].template cast<double>() - n).norm(), 0, 1e-12);
  }
  EXPECT_EQ(buffers, 3u * 6u * 4u);
  for (int s = 0; s < 60; ++s) sim.advance();  // 0.12 s at 1 m/s: each column crosses about once
  const auto& fl = sim.flow();
  EXPECT_GE(fl.created, 24);
  EXPECT_LE(std::abs(fl.mass_in - fl.mass_out() - (sim.fluid_mass() - fl.mass0)), 1e-12 * fl.mass0);
  std::size_t after = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) after += zone[i] == 0;
  EXPECT_EQ(after, 72u);  // every column keeps its 3 lattice particles
}

#endif  // VARSPH_OBLIQUE_VALIDATION
