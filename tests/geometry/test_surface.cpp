// Surface sampling (layer 0) of a unit cube and an icosphere: counts, distance to the mesh,
// normals, area shares, spacing, determinism.
#include "test_helpers.h"
#include "varsph/geometry/sample_body.h"

using namespace varsph::geometry;

namespace {

BodyRequest surface_request(const std::filesystem::path& p, double dx, int layers = 1) {
  BodyRequest r;
  r.mesh = p;
  r.dimension = 3;
  r.fill = "surface";
  r.layers = layers;
  r.spacing = dx;
  return r;
}

}  // namespace

TEST(SurfaceSampling, UnitCubeGivesSquareLatticeOnEachFace) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  vt::write_off(dir / "cube.off", V, F);
  const double dx = 0.05;
  const SampledBody b = sample_body(surface_request(dir / "cube.off", dx));
  EXPECT_NEAR(b.surface_measure, 6.0, 1e-12);
  EXPECT_NEAR(b.enclosed_measure, 1.0, 1e-12);
  const double expected = 6.0 / (dx * dx);
  EXPECT_NEAR(b.positions.rows(), expected, 0.03 * expected);
  EXPECT_EQ(b.positions.rows(), 2400);  // exact: 20 x 20 per face
  EXPECT_NEAR(b.measure.sum(), 6.0, 1e-9);
  for (int i = 0; i < b.positions.rows(); ++i) {
    const Eigen::Vector3d p = b.positions.row(i);
    EXPECT_LT(vt::mesh_distance(p, V, F), 0.01 * dx);
    // the face the particle sits on, its exact outward normal, and the lattice (i + 1/2) dx
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(p[k] - 0.5) > std::abs(p[axis] - 0.5)) axis = k;
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    n[axis] = p[axis] > 0.5 ? 1 : -1;
    EXPECT_GT(b.normals.row(i).dot(n), 0.99);
    for (int k = 0; k < 3; ++k) {
      if (k == axis) continue;
      const double c = p[k] / dx - 0.5;
      EXPECT_NEAR(c, std::round(c), 1e-9) << "not on the cell-centred lattice: " << p.transpose();
    }
    EXPECT_NEAR(b.measure[i], dx * dx, 1e-12);
  }
  EXPECT_GE(vt::min_pair_distance(b.positions, dx), 0.5 * dx);
}

TEST(SurfaceSampling, SphereCountDistanceNormals) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::icosphere(0.5, 4, V, F);
  vt::write_off(dir / "sphere.off", V, F);
  const double dx = 0.04;
  const SampledBody b = sample_body(surface_request(dir / "sphere.off", dx));
  const double expected = b.surface_measure / (dx * dx);
  EXPECT_NEAR(b.positions.rows(), expected, 0.03 * expected);
  EXPECT_NEAR(b.measure.sum(), b.surface_measure, 1e-9 * b.surface_measure);
  for (int i = 0; i < b.positions.rows(); ++i) {
    const Eigen::Vector3d p = b.positions.row(i);
    EXPECT_LT(vt::mesh_distance(p, V, F), 0.01 * dx);
    EXPECT_GT(b.normals.row(i).dot(p.normalized()), 0.99);
    EXPECT_NEAR(b.normals.row(i).norm(), 1.0, 1e-12);
  }
  EXPECT_GE(vt::min_pair_distance(b.positions, dx), 0.5 * dx);
}

TEST(SurfaceSampling, IsDeterministic) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::icosphere(0.3, 3, V, F);
  vt::write_off(dir / "sphere.off", V, F);
  const SampledBody a = sample_body(surface_request(dir / "sphere.off", 0.05, 2));
  const SampledBody b = sample_body(surface_request(dir / "sphere.off", 0.05, 2));
  ASSERT_EQ(a.positions.rows(), b.positions.rows());
  EXPECT_TRUE((a.positions.array() == b.positions.array()).all());
  EXPECT_TRUE((a.measure.array() == b.measure.array()).all());
}

TEST(SurfaceSampling, CylinderHasNoCloseParticles) {
  const auto dir = vt::temp_dir();
  // closed cylinder R = 0.3, H = 0.6, 48 sides
  const int n = 48;
  vt::MatrixXd V(2 * n + 2, 3); vt::MatrixXi F(4 * n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    V.row(2 * i) << 0.3 * std::cos(a), 0.3 * std::sin(a), 0;
    V.row(2 * i + 1) << 0.3 * std::cos(a), 0.3 * std::sin(a), 0.6;
  }
  V.row(2 * n) << 0, 0, 0;
  V.row(2 * n + 1) << 0, 0, 0.6;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    F.row(4 * i) << 2 * i, 2 * j, 2 * j + 1;
    F.row(4 * i + 1) << 2 * i, 2 * j + 1, 2 * i + 1;
    F.row(4 * i + 2) << 2 * n, 2 * j, 2 * i;
    F.row(4 * i + 3) << 2 * n + 1, 2 * i + 1, 2 * j + 1;
  }
  vt::write_off(dir / "cyl.off", V, F);
  const double dx = 0.03;
  const SampledBody b = sample_body(surface_request(dir / "cyl.off", dx, 3));
  EXPECT_GE(vt::min_pair_distance(b.positions, dx), 0.5 * dx);
  const int n0 = static_cast<int>((b.layer.array() == 0).count());
  const double expected = b.surface_measure / (dx * dx);
  EXPECT_NEAR(n0, expected, 0.05 * expected);
  for (int i = 0; i < b.positions.rows(); ++i)
    EXPECT_NEAR(vt::mesh_distance(b.positions.row(i), V, F), b.layer[i] * dx, 0.01 * dx);
}
