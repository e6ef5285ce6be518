// The stock meshes of geometry/meshes/ load, are closed, and have their stated sizes.
#include "test_helpers.h"
#include "varsph/geometry/sample_body.h"

using namespace varsph::geometry;

namespace {
const std::filesystem::path kMeshes = std::filesystem::path(VARSPH_SOURCE_DIR) / "geometry" / "meshes";

SampledBody load(const std::string& name, const std::string& fill, double dx, int dim = 3) {
  BodyRequest r;
  r.mesh = kMeshes / name;
  r.fill = fill;
  r.spacing = dx;
  r.dimension = dim;
  return sample_body(r);
}
}  // namespace

TEST(StockMeshes, Spheric2TankObstacleWater) {
  const SampledBody tank = load("spheric2_tank.off", "surface", 0.05);
  EXPECT_NEAR(tank.enclosed_measure, 3.22 * 1.0 * 1.0, 1e-9);
  EXPECT_TRUE(tank.notes.empty());
  const SampledBody box = load("spheric2_obstacle.off", "surface", 0.02);
  EXPECT_NEAR(box.enclosed_measure, 0.161 * 0.403 * 0.161, 1e-9);
  EXPECT_NEAR(box.positions.col(0).minCoeff(), 0.6635, 0.02);
  const SampledBody water = load("spheric2_water.off", "volume", 0.02);
  EXPECT_NEAR(water.enclosed_measure, 1.228 * 1.0 * 0.55, 1e-9);
  // cell-centred lattice: round(1.228 / 0.02) x 1 / 0.02 x (0.55 / 0.02 rounded down at the exact half)
  EXPECT_EQ(water.positions.rows(), 61 * 50 * 27);
}

TEST(StockMeshes, CylinderAndSloshingTank) {
  const SampledBody c = load("cylinder.off", "volume", 0.02);
  EXPECT_NEAR(c.enclosed_measure, M_PI * 0.25 * 0.25 * 0.5, 0.01 * M_PI * 0.25 * 0.25 * 0.5);
  const SampledBody s = load("sloshing_tank.off", "surface", 0.05);
  EXPECT_NEAR(s.enclosed_measure, 0.6 * 0.3 * 0.4, 1e-12);
  EXPECT_EQ(s.positions.rows(), 2 * (12 * 6 + 12 * 8 + 6 * 8));
}

TEST(StockMeshes, Tank2D) {
  const SampledBody t = load("tank2d.poly2d", "surface", 0.01, 2);
  EXPECT_NEAR(t.surface_measure, 0.6 + 0.58 + 0.6, 1e-12);
  EXPECT_EQ(t.positions.rows(), 179);
}

TEST(StockMeshes, SpacingThatDoesNotDivideTheSides) {
  // 0.6 x 0.3 x 0.4 m with dx = 0.035: no side is a multiple of dx
  for (const std::string side : {"outside", "inside"}) {
    BodyRequest r;
    r.mesh = kMeshes / "sloshing_tank.off";
    r.spacing = 0.035;
    r.layers = 3;
    r.layer_side = side;
    const SampledBody b = sample_body(r);
    const double expected = b.surface_measure / (r.spacing * r.spacing);
    const long n0 = (b.layer.array() == 0).count();
    EXPECT_NEAR(n0, expected, 0.03 * expected) << side;
    double share0 = 0;
    for (int i = 0; i < b.positions.rows(); ++i)
      if (b.layer[i] == 0) share0 += b.measure[i];
    EXPECT_NEAR(share0, b.surface_measure, 1e-9) << side;
    EXPECT_GE(vt::min_pair_distance(b.positions, r.spacing), 0.5 * r.spacing) << side;
    vt::MatrixXd V(8, 3); vt::MatrixXi F;
    vt::cube(1.0, V, F);
    V.col(0) *= 0.6; V.col(1) *= 0.3; V.col(2) *= 0.4;
    for (int i = 0; i < b.positions.rows(); ++i)
      EXPECT_NEAR(vt::mesh_distance(b.positions.row(i), V, F), b.layer[i] * r.spacing, 0.01 * r.spacing);
  }
}
