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
