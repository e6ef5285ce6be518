// No holes: every point of the surface (and of each outer offset surface) has a particle of its
// layer within about one spacing.
#include <random>

#include "test_helpers.h"
#include "varsph/geometry/sample_body.h"

using namespace varsph::geometry;

namespace {

// largest distance from the query points Q to the nearest row of X (brute force)
double max_gap(const std::vector<Eigen::Vector3d>& Q, const Eigen::MatrixXd& X) {
  double worst = 0;
  for (const auto& q : Q) {
    double best = INFINITY;
    for (int i = 0; i < X.rows(); ++i) best = std::min(best, (X.row(i).transpose() - q).squaredNorm());
    worst = std::max(worst, std::sqrt(best));
  }
  return worst;
}

Eigen::MatrixXd rows_of_layer(const SampledBody& b, int k) {
  Eigen::MatrixXd X((b.layer.array() == k).count(), 3);
  for (int i = 0, j = 0; i < b.positions.rows(); ++i)
    if (b.layer[i] == k) X.row(j++) = b.positions.row(i);
  return X;
}

}  // namespace

TEST(Coverage, CubeSurfaceAndOuterLayersHaveNoHoles) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  vt::write_off(dir / "cube.off", V, F);
  const double dx = 0.1;
  BodyRequest r;
  r.mesh = dir / "cube.off";
  r.spacing = dx;
  r.layers = 3;
  const SampledBody b = sample_body(r);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.4, 1.4);
  for (int k = 0; k < 3; ++k) {
    // points of the offset surface at k dx: the closest cube point plus k dx away from it
    std::vector<Eigen::Vector3d> Q;
    while (Q.size() < 3000) {
      const Eigen::Vector3d q(u(rng), u(rng), u(rng));
      const Eigen::Vector3d c = q.cwiseMax(0.0).cwiseMin(1.0);
      if ((q - c).norm() < 1e-9) continue;  // inside
      Q.push_back(c + k * dx * (q - c).normalized());
    }
    const double gap = max_gap(Q, rows_of_layer(b, k));
    EXPECT_LE(gap, (k == 0 ? 0.75 : 1.0) * dx) << "layer " << k;
  }
}

TEST(Coverage, SphereSurfaceHasNoHoles) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::icosphere(0.5, 4, V, F);
  vt::write_off(dir / "sphere.off", V, F);
  const double dx = 0.05;
  BodyRequest r;
  r.mesh = dir / "sphere.off";
  r.spacing = dx;
  const SampledBody b = sample_body(r);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Eigen::Vector3d> Q;
  for (int i = 0; i < 3000; ++i) {  // uniform points on random triangles
    const int f = static_cast<int>(rng() % F.rows());
    double a = u(rng), c = u(rng);
    if (a + c > 1) { a = 1 - a; c = 1 - c; }
    Q.push_back(V.row(F(f, 0)).transpose() + a * (V.row(F(f, 1)) - V.row(F(f, 0))).transpose() +
                c * (V.row(F(f, 2)) - V.row(F(f, 0))).transpose());
  }
  EXPECT_LE(max_gap(Q, b.positions), 1.0 * dx);
}
