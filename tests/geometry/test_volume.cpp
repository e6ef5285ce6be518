// Volume (fluid) fill: cell-centred lattice inside closed meshes, clip box, exclusion distance.
#include "test_helpers.h"
#include "varsph/geometry/sample_body.h"

using namespace varsph::geometry;

TEST(VolumeFill, UnitCubeIsCellCentredLattice) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  vt::write_off(dir / "cube.off", V, F);
  BodyRequest r;
  r.mesh = dir / "cube.off";
  r.fill = "volume";
  r.spacing = 0.05;
  const SampledBody b = sample_body(r);
  EXPECT_EQ(b.positions.rows(), 8000);
  EXPECT_NEAR(b.positions.rows(), 1.0 / std::pow(0.05, 3), 0.02 * 8000);
  EXPECT_EQ(b.normals.rows(), 0);
  EXPECT_NEAR(b.measure[0], std::pow(0.05, 3), 1e-15);
  for (int i = 0; i < b.positions.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      const double c = b.positions(i, k) / 0.05 - 0.5;
      EXPECT_NEAR(c, std::round(c), 1e-9);
    }
}

TEST(VolumeFill, SphereCountMatchesVolume) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::icosphere(0.5, 4, V, F);
  vt::write_off(dir / "sphere.off", V, F);
  BodyRequest r;
  r.mesh = dir / "sphere.off";
  r.fill = "volume";
  r.spacing = 0.025;
  const SampledBody b = sample_body(r);
  const double expected = b.enclosed_measure / std::pow(r.spacing, 3);
  EXPECT_NEAR(b.positions.rows(), expected, 0.02 * expected);
  for (int i = 0; i < b.positions.rows(); ++i) EXPECT_LT(b.positions.row(i).norm(), 0.5);
}

TEST(VolumeFill, ClipBoxAndExclusion) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  vt::write_off(dir / "cube.off", V, F);
  BodyRequest r;
  r.mesh = dir / "cube.off";
  r.fill = "volume";
  r.spacing = 0.1;
  r.clip_min = Eigen::Vector3d(0, 0, 0);
  r.clip_max = Eigen::Vector3d(1, 1, 0.55);  // water column of height 0.55: 5 full layers
  SampledBody b = sample_body(r);
  EXPECT_EQ(b.positions.rows(), 10 * 10 * 5);
  EXPECT_LT(b.positions.col(2).maxCoeff(), 0.55);
  // exclusion: remove points closer than 0.25 to the point (0.05, 0.05, 0.05)
  r.exclusion_points = Eigen::RowVector3d(0.05, 0.05, 0.05);
  r.exclusion_distance = 0.15;
  b = sample_body(r);
  // removed: (0.05,0.05,0.05) and its 3 axis neighbours at 0.1 plus 3 diagonal at 0.141
  EXPECT_EQ(b.positions.rows(), 500 - 7);
  EXPECT_TRUE(vt::has_note(b.notes, "removed 7 fluid points"));
}

TEST(VolumeFill, RotatedCubeMatchesAnalyticInsideTest) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  vt::write_off(dir / "cube.off", V, F);
  BodyRequest r;
  r.mesh = dir / "cube.off";
  r.fill = "volume";
  r.spacing = 0.05;
  Eigen::Affine3d T = Eigen::Translation3d(0.3, -0.2, 0.1) * Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()) *
                      Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitX());
  r.transform = T.matrix();
  r.clip_min = Eigen::Vector3d(-2, -2, -2);
  r.clip_max = Eigen::Vector3d(2, 2, 2);
  const SampledBody b = sample_body(r);
  // the same lattice, classified analytically
  long expected = 0;
  const Eigen::Affine3d Ti = T.inverse();
  for (int k = 0; k < 80; ++k)
    for (int j = 0; j < 80; ++j)
      for (int i = 0; i < 80; ++i) {
        const Eigen::Vector3d p = Eigen::Vector3d(-2, -2, -2) + 0.05 * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
        const Eigen::Vector3d q = Ti * p;
        if ((q.array() > 1e-12).all() && (q.array() < 1 - 1e-12).all()) ++expected;
      }
  EXPECT_EQ(b.positions.rows(), expected);
  EXPECT_NEAR(b.positions.rows(), 8000, 0.02 * 8000);
  for (int i = 0; i < b.positions.rows(); ++i) {
    const Eigen::Vector3d q = Ti * Eigen::Vector3d(b.positions.row(i).transpose());
    EXPECT_TRUE((q.array() > 0).all() && (q.array() < 1).all()) << q.transpose();
  }
}
