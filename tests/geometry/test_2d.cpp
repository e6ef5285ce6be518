// 2D: .poly2d loops, open polylines, sections of 3D meshes, layers, point-in-polygon fill.
#include "test_helpers.h"
#include "varsph/geometry/geometry_error.h"
#include "varsph/geometry/sample_body.h"

using namespace varsph::geometry;

namespace {

BodyRequest req2(const std::filesystem::path& p, double dx, int layers = 1, std::string side = "outside") {
  BodyRequest r;
  r.mesh = p;
  r.dimension = 2;
  r.spacing = dx;
  r.layers = layers;
  r.layer_side = side;
  return r;
}

double polyline_distance(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& P, bool closed) {
  double d = INFINITY;
  const std::size_t n = P.size();
  for (std::size_t i = 0; i + 1 < n + (closed ? 1 : 0); ++i) {
    const Eigen::Vector2d a = P[i], b = P[(i + 1) % n];
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    d = std::min(d, (a + t * (b - a) - p).norm());
  }
  return d;
}

}  // namespace

TEST(Curves2D, SquareHasCornersAndExactCount) {
  const auto dir = vt::temp_dir();
  std::ofstream(dir / "sq.poly2d") << "# unit square, clockwise on purpose\n0 0\n0 1\n1 1\n1 0\n";
  const SampledBody b = sample_body(req2(dir / "sq.poly2d", 0.1));
  EXPECT_EQ(b.positions.rows(), 40);
  EXPECT_NEAR(b.surface_measure, 4.0, 1e-12);
  EXPECT_NEAR(b.enclosed_measure, 1.0, 1e-12);
  EXPECT_TRUE(vt::has_note(b.notes, "reversed 1 loops"));
  EXPECT_NEAR(b.measure.sum(), 4.0, 1e-12);
  int corners = 0;
  for (int i = 0; i < b.positions.rows(); ++i) {
    const Eigen::Vector2d p = b.positions.row(i), n = b.normals.row(i);
    EXPECT_GT(n.dot(p - Eigen::Vector2d(0.5, 0.5)), 0);  // outward
    const bool corner = (std::abs(p.x() - 0.5) > 0.499) && (std::abs(p.y() - 0.5) > 0.499);
    if (corner) {
      ++corners;
      EXPECT_NEAR(std::abs(n.x()), std::sqrt(0.5), 1e-12);
    }
  }
  EXPECT_EQ(corners, 4);
}

TEST(Curves2D, CircleCountAndNormals) {
  const auto dir = vt::temp_dir();
  {
    std::ofstream o(dir / "circle.poly2d");
    o.precision(17);
    for (int i = 0; i < 360; ++i) o << 0.5 * std::cos(2 * M_PI * i / 360) << " " << 0.5 * std::sin(2 * M_PI * i / 360) << "\n";
  }
  const double dx = 0.01;
  const SampledBody b = sample_body(req2(dir / "circle.poly2d", dx, 3, "inside"));
  const int n0 = static_cast<int>((b.layer.array() == 0).count());
  EXPECT_NEAR(n0, b.surface_measure / dx, 0.03 * b.surface_measure / dx);
  for (int i = 0; i < b.positions.rows(); ++i) {
    const Eigen::Vector2d p = b.positions.row(i);
    EXPECT_GT(b.normals.row(i).dot(p.normalized()), 0.99);
    EXPECT_NEAR(p.norm(), 0.5 - b.layer[i] * dx, 0.01 * dx);  // polygon vs circle: 0.5(1-cos(0.5 deg)) = 1.9e-5
  }
  EXPECT_GE(vt::min_pair_distance(b.positions, dx), 0.5 * dx);
}

TEST(Curves2D, OpenTankLayersOutside) {
  const auto dir = vt::temp_dir();
  std::ofstream(dir / "tank.poly2d") << "open\n0 0.6\n0 0\n0.58 0\n0.58 0.6\n";
  const double dx = 0.01;
  const SampledBody b = sample_body(req2(dir / "tank.poly2d", dx, 3, "outside"));
  EXPECT_EQ((b.layer.array() == 0).count(), 60 + 58 + 60 + 1);
  const std::vector<Eigen::Vector2d> P = {{0, 0.6}, {0, 0}, {0.58, 0}, {0.58, 0.6}};
  for (int i = 0; i < b.positions.rows(); ++i) {
    const Eigen::Vector2d p = b.positions.row(i);
    EXPECT_NEAR(polyline_distance(p, P, false), b.layer[i] * dx, 0.01 * dx);
    if (b.layer[i] > 0) {
      EXPECT_TRUE(p.x() < 0 || p.x() > 0.58 || p.y() < 0) << p.transpose();  // in the wall
    }
  }
  EXPECT_GE(vt::min_pair_distance(b.positions, dx), 0.5 * dx);
  EXPECT_EQ(b.enclosed_measure, 0.0);
  // an open polyline cannot be volume-filled
  BodyRequest v = req2(dir / "tank.poly2d", dx);
  v.fill = "volume";
  EXPECT_THROW(sample_body(v), GeometryError);
}

TEST(Curves2D, SquareLayersInsideAndOutside) {
  const auto dir = vt::temp_dir();
  std::ofstream(dir / "sq.poly2d") << "0 0\n1 0\n1 1\n0 1\n";
  const std::vector<Eigen::Vector2d> P = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const std::string side : {"inside", "outside"}) {
    const SampledBody b = sample_body(req2(dir / "sq.poly2d", 0.05, 4, side));
    for (int i = 0; i < b.positions.rows(); ++i)
      EXPECT_NEAR(polyline_distance(b.positions.row(i), P, true), b.layer[i] * 0.05, 0.01 * 0.05);
    EXPECT_GE(vt::min_pair_distance(b.positions, 0.05), 0.5 * 0.05) << side;
  }
}

TEST(Curves2D, VolumeFillWithHole) {
  const auto dir = vt::temp_dir();
  std::ofstream(dir / "ring.poly2d") << "0 0\n1 0\n1 1\n0 1\n\n# hole\n0.2 0.2\n0.2 0.6\n0.6 0.6\n0.6 0.2\n";
  BodyRequest r = req2(dir / "ring.poly2d", 0.1);
  r.fill = "volume";
  const SampledBody b = sample_body(r);
  EXPECT_EQ(b.positions.rows(), 100 - 16);
  EXPECT_NEAR(b.enclosed_measure, 1.0 - 0.16, 1e-12);
}

TEST(Curves2D, SectionOfA3DMesh) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  vt::write_off(dir / "cube.off", V, F);
  BodyRequest r = req2(dir / "cube.off", 0.1);
  r.section_point = Eigen::Vector3d(0.5, 0.5, 0.5);
  r.section_normal = Eigen::Vector3d::UnitY();  // (x, z) plane
  SampledBody b = sample_body(r);
  EXPECT_EQ(b.positions.rows(), 40);
  EXPECT_NEAR(b.enclosed_measure, 1.0, 1e-9);
  r.fill = "volume";
  b = sample_body(r);
  EXPECT_EQ(b.positions.rows(), 100);
  r.section_point = Eigen::Vector3d(0, 5, 0);
  EXPECT_THROW(sample_body(r), GeometryError);
}

TEST(Curves2D, SectionOfASphereIsACircle) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::icosphere(0.5, 4, V, F);
  vt::write_off(dir / "sphere.off", V, F);
  BodyRequest r = req2(dir / "sphere.off", 0.02, 2, "inside");
  r.section_point = Eigen::Vector3d(0, 0, 0.1);
  r.section_normal = Eigen::Vector3d(0, 0, 2.0);  // (x, y) plane at z = 0.1
  const SampledBody b = sample_body(r);
  const double R = std::sqrt(0.25 - 0.01);
  EXPECT_NEAR(b.surface_measure, 2 * M_PI * R, 0.01 * 2 * M_PI * R);
  const long n0 = (b.layer.array() == 0).count();
  EXPECT_NEAR(n0, b.surface_measure / 0.02, 0.03 * b.surface_measure / 0.02);
  for (int i = 0; i < b.positions.rows(); ++i) {
    const Eigen::Vector2d p = b.positions.row(i);
    EXPECT_NEAR(p.norm(), R - b.layer[i] * 0.02, 0.01);  // faceted sphere: within 1 cm
    EXPECT_GT(b.normals.row(i).dot(p.normalized()), 0.99);
  }
  EXPECT_GE(vt::min_pair_distance(b.positions, 0.02), 0.5 * 0.02);
}

TEST(Curves2D, RepeatedPointsAreIgnored) {
  const auto dir = vt::temp_dir();
  std::ofstream(dir / "sq.poly2d") << "0 0\n1 0\n1 0\n1 1\n0 1\n0 0\n";
  const SampledBody b = sample_body(req2(dir / "sq.poly2d", 0.1, 2));
  EXPECT_EQ((b.layer.array() == 0).count(), 40);
  EXPECT_GE(vt::min_pair_distance(b.positions, 0.1), 0.05);
}
