// Mass properties of uniform solids (bodies/mass_properties.hpp) against closed forms, and the exact
// mesh and polygon integrals against the shapes they tessellate.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bodies/mass_properties.hpp"

using namespace varsph::bodies;
using Eigen::Vector3d;

namespace {

// A box [lo, hi] as 12 outward-wound triangles.
void box_mesh(const Vector3d& lo, const Vector3d& hi, std::vector<Vector3d>& V, std::vector<Eigen::Vector3i>& F) {
  V.clear();
  for (int k = 0; k < 8; ++k) V.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
  F = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
       {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
}

// A prism of n sides approximating a cylinder of radius R about z, length L, centred at c.
void prism_mesh(int n, double R, double L, const Vector3d& c, std::vector<Vector3d>& V, std::vector<Eigen::Vector3i>& F) {
  V.clear();
  F.clear();
  for (int k = 0; k < n; ++k) {
    const double a = 2 * std::numbers::pi * k / n;
    V.emplace_back(c + Vector3d(R * std::cos(a), R * std::sin(a), -L / 2));
    V.emplace_back(c + Vector3d(R * std::cos(a), R * std::sin(a), L / 2));
  }
  V.push_back(c - Vector3d(0, 0, L / 2));
  V.push_back(c + Vector3d(0, 0, L / 2));
  const int b = 2 * n, t = 2 * n + 1;
  for (int k = 0; k < n; ++k) {
    const int i0 = 2 * k, i1 = 2 * ((k + 1) % n);
    F.emplace_back(i0, i1, i0 + 1);
    F.emplace_back(i1, i1 + 1, i0 + 1);
    F.emplace_back(b, i1, i0);
    F.emplace_back(t, i0 + 1, i1 + 1);
  }
}

}  // namespace

TEST(MassProperties, BoxMatchesClosedForms2DAnd3D) {
  const auto m = box_mass({1, 2, 3}, {1.5, 2.2, 3.1}, 500, 3);
  EXPECT_NEAR(m.mass, 500 * 0.5 * 0.2 * 0.1, 1e-12);
  EXPECT_NEAR(m.com.x(), 1.25, 1e-14);
  EXPECT_NEAR(m.inertia(0, 0), m.mass * (0.04 + 0.01) / 12, 1e-14);
  EXPECT_NEAR(m.inertia(2, 2), m.mass * (0.25 + 0.04) / 12, 1e-14);
  const auto r = box_mass({0, 0, 0}, {0.3, 0.2, 0}, 500, 2);
  EXPECT_NEAR(r.mass, 30, 1e-12);  // kg per metre
  EXPECT_NEAR(r.inertia(2, 2), 30 * (0.09 + 0.04) / 12, 1e-13);
}

TEST(MassProperties, BallDiscAndCylinder) {
  const auto s = ball_mass({0, 0, 0}, 0.5, 1000, 3);
  EXPECT_NEAR(s.mass, 1000 * 4.0 / 3 * std::numbers::pi * 0.125, 1e-9);
  EXPECT_NEAR(s.inertia(1, 1), 0.4 * s.mass * 0.25, 1e-9);
  const auto d = ball_mass({0, 0, 0}, 1.0, 1200, 2);
  EXPECT_NEAR(d.inertia(2, 2), 0.5 * d.mass, 1e-9);
  const auto c = cylinder_mass({0, 0, 0}, 0.1, {0, 0, 2}, 0.4, 800, 3);
  EXPECT_NEAR(c.inertia(2, 2), 0.5 * c.mass * 0.01, 1e-12);
  EXPECT_NEAR(c.inertia(0, 0), c.mass * (3 * 0.01 + 0.16) / 12, 1e-12);
  // an oblique axis: the same tensor rotated (trace and the moment about the axis are invariants)
  const Vector3d e = Vector3d(1, 1, 0).normalized();
  const auto o = cylinder_mass({0, 0, 0}, 0.1, e, 0.4, 800, 3);
  EXPECT_NEAR(e.dot(o.inertia * e), 0.5 * c.mass * 0.01, 1e-12);
  EXPECT_NEAR(o.inertia.trace(), c.inertia.trace(), 1e-12);
}

TEST(MassProperties, TriangleMeshOfABoxIsExactFarFromTheOrigin) {
  std::vector<Vector3d> V;
  std::vector<Eigen::Vector3i> F;
  const Vector3d lo(1000.2, -500.0, 20.0), hi(1000.7, -499.8, 20.3);
  box_mesh(lo, hi, V, F);
  const auto m = triangle_mesh_mass(V, F, 700);
  const auto b = box_mass(lo, hi, 700, 3);
  EXPECT_NEAR(m.mass, b.mass, 1e-9 * b.mass);
  EXPECT_NEAR((m.com - b.com).norm(), 0, 1e-9);
  EXPECT_NEAR((m.inertia - b.inertia).norm(), 0, 1e-8 * b.inertia.norm());
}

TEST(MassProperties, TriangleMeshOfAFinePrismApproachesTheCylinder) {
  std::vector<Vector3d> V;
  std::vector<Eigen::Vector3i> F;
  prism_mesh(720, 0.2, 0.5, {0.1, 0.2, 0.3}, V, F);
  const auto m = triangle_mesh_mass(V, F, 1000);
  const auto c = cylinder_mass({0.1, 0.2, 0.3}, 0.2, {0, 0, 1}, 0.5, 1000, 3);
  // a regular n-gon holds (n / 2pi) sin(2pi / n) of the disc's area: 1.3e-5 short at n = 720
  EXPECT_NEAR(m.mass / c.mass, 1.0, 2e-5);
  EXPECT_NEAR((m.com - c.com).norm(), 0, 1e-12);
  EXPECT_NEAR(m.inertia(2, 2) / c.inertia(2, 2), 1.0, 5e-5);
  EXPECT_NEAR(m.inertia(0, 0) / c.inertia(0, 0), 1.0, 5e-5);
  EXPECT_NEAR(m.inertia(0, 1), 0.0, 1e-12);
}

TEST(MassProperties, PolygonWithAHoleAndTheParallelAxisTheorem) {
  using P = Eigen::Vector2d;
  const std::vector<std::vector<P>> square = {{P(0, 0), P(2, 0), P(2, 2), P(0, 2)}};
  const auto s = polygon_mass(square, 3);
  const auto b = box_mass({0, 0, 0}, {2, 2, 0}, 3, 2);
  EXPECT_NEAR(s.mass, b.mass, 1e-12);
  EXPECT_NEAR(s.inertia(2, 2), b.inertia(2, 2), 1e-12);
  // a square frame: the outer square minus a clockwise inner one
  const std::vector<std::vector<P>> frame = {{P(0, 0), P(2, 0), P(2, 2), P(0, 2)}, {P(0.5, 0.5), P(0.5, 1.5), P(1.5, 1.5), P(1.5, 0.5)}};
  const auto f = polygon_mass(frame, 3);
  const auto inner = box_mass({0.5, 0.5, 0}, {1.5, 1.5, 0}, 3, 2);
  EXPECT_NEAR(f.mass, b.mass - inner.mass, 1e-12);
  EXPECT_NEAR(f.inertia(2, 2), b.inertia(2, 2) - inner.inertia(2, 2), 1e-12);
  EXPECT_NEAR(f.com.x(), 1.0, 1e-14);
  // Steiner: about a corner of the full square, I + M d^2
  EXPECT_NEAR(inertia_about(b, {0, 0, 0})(2, 2), b.inertia(2, 2) + b.mass * 2.0, 1e-12);
}
