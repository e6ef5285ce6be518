// Offset layers: each layer at distance k dx from the surface, no two particles closer than dx/2.
#include "test_helpers.h"
#include "varsph/geometry/sample_body.h"

using namespace varsph::geometry;

namespace {

void check_layers(const std::filesystem::path& mesh, const vt::MatrixXd& V, const vt::MatrixXi& F,
                  double dx, int layers, const std::string& side, bool closed_box) {
  BodyRequest r;
  r.mesh = mesh;
  r.dimension = 3;
  r.layers = layers;
  r.layer_side = side;
  r.spacing = dx;
  const SampledBody b = sample_body(r);
  ASSERT_EQ(b.layer.maxCoeff(), layers - 1);
  const Eigen::Vector3d c = V.colwise().mean();
  for (int i = 0; i < b.positions.rows(); ++i) {
    const Eigen::Vector3d p = b.positions.row(i);
    EXPECT_NEAR(vt::mesh_distance(p, V, F), b.layer[i] * dx, 0.01 * dx) << p.transpose();
    // on the requested side (inside/outside of the convex test bodies)
    if (b.layer[i] > 0 && closed_box) {
      const bool outside = ((p - c).array().abs() > 0.5 + 1e-9).any();
      EXPECT_EQ(outside, side == "outside") << p.transpose();
    }
  }
  EXPECT_GE(vt::min_pair_distance(b.positions, dx), 0.5 * dx);
  // every layer keeps about one particle per dx^2 of its own offset surface (flat parts exact)
  for (int k = 0; k < layers; ++k) EXPECT_GT((b.layer.array() == k).count(), 0);
}

}  // namespace

TEST(Layers, CubeOutsideLayersAreAtOffsets) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  V.array() -= 0.5;  // centred, so the inside/outside check above works
  vt::write_off(dir / "cube.off", V, F);
  check_layers(dir / "cube.off", V, F, 0.1, 3, "outside", true);
}

TEST(Layers, CubeInsideLayersAreAtOffsets) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  V.array() -= 0.5;
  vt::write_off(dir / "cube.off", V, F);
  check_layers(dir / "cube.off", V, F, 0.1, 3, "inside", true);
  // the inner layers of a box are square lattices of the shrunk box: (n - 2k)^2 per face
  BodyRequest r;
  r.mesh = dir / "cube.off";
  r.layers = 3;
  r.layer_side = "inside";
  r.spacing = 0.1;
  const SampledBody b = sample_body(r);
  EXPECT_EQ((b.layer.array() == 1).count(), 6 * 8 * 8);
  EXPECT_EQ((b.layer.array() == 2).count(), 6 * 6 * 6);
}

TEST(Layers, SphereBothSides) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::icosphere(0.5, 3, V, F);
  vt::write_off(dir / "sphere.off", V, F);
  check_layers(dir / "sphere.off", V, F, 0.06, 3, "inside", false);
  check_layers(dir / "sphere.off", V, F, 0.06, 3, "outside", false);
}

TEST(Layers, LShapedPrismConcaveEdges) {
  const auto dir = vt::temp_dir();
  // L-shaped prism (concave edge along z), 2D outline extruded by 0.4
  const double P[6][2] = {{0, 0}, {1, 0}, {1, 0.4}, {0.4, 0.4}, {0.4, 1}, {0, 1}};
  vt::MatrixXd V(12, 3);
  for (int i = 0; i < 6; ++i) {
    V.row(i) << P[i][0], P[i][1], 0;
    V.row(i + 6) << P[i][0], P[i][1], 0.4;
  }
  std::vector<Eigen::Vector3i> f;
  // caps (bottom faces down: clockwise seen from above), as fans of the convex pieces
  const int cap[4][3] = {{0, 3, 1}, {1, 3, 2}, {0, 5, 3}, {3, 5, 4}};
  for (auto& t : cap) {
    f.push_back({t[0], t[1], t[2]});
    f.push_back({t[0] + 6, t[2] + 6, t[1] + 6});
  }
  for (int i = 0; i < 6; ++i) {
    const int j = (i + 1) % 6;
    f.push_back({i, j, j + 6});
    f.push_back({i, j + 6, i + 6});
  }
  vt::MatrixXi F(static_cast<int>(f.size()), 3);
  for (std::size_t i = 0; i < f.size(); ++i) F.row(static_cast<int>(i)) = f[i].transpose();
  vt::write_off(dir / "l.off", V, F);
  check_layers(dir / "l.off", V, F, 0.05, 3, "outside", false);
  check_layers(dir / "l.off", V, F, 0.05, 3, "inside", false);
}
