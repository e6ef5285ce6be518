// Samples a 3D tank into ~1e6 boundary particles and fills ~1e6 fluid particles; prints seconds.
// Usage: bench_geometry [MESH_DIR]   (default: the source tree's geometry/meshes)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "varsph/geometry/points_far_from.h"
#include "varsph/geometry/sample_body.h"

using namespace varsph::geometry;

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path dir = argc > 1 ? argv[1] : VARSPH_GEOMETRY_MESH_DIR;
  // SPHERIC 2 tank: area 2 (3.22 + 3.22 + 1) = 14.88 m^2 -> dx = 3.86 mm gives ~1e6 particles
  const double dx_wall = 0.00386;
  BodyRequest tank;
  tank.mesh = dir / "spheric2_tank.off";
  tank.spacing = dx_wall;
  tank.layers = 1;
  auto t0 = std::chrono::steady_clock::now();
  const SampledBody walls = sample_body(tank);
  const double t_surface = seconds_since(t0);
  std::printf("surface: %ld boundary particles (1 layer, dx = %.5f m) in %.3f s\n",
              static_cast<long>(walls.positions.rows()), dx_wall, seconds_since(t0));

  // 3 layers at a coarser spacing (same particle count order): exercises the offset surfaces
  BodyRequest tank3 = tank;
  tank3.layers = 3;
  tank3.spacing = std::sqrt(3.0) * dx_wall;
  t0 = std::chrono::steady_clock::now();
  const SampledBody walls3 = sample_body(tank3);
  std::printf("surface: %ld boundary particles (3 layers, dx = %.5f m) in %.3f s\n",
              static_cast<long>(walls3.positions.rows()), tank3.spacing, seconds_since(t0));

  // water column 1.228 x 1 x 0.55 m = 0.6754 m^3 -> dx = 8.77 mm gives ~1e6 particles
  BodyRequest water;
  water.mesh = dir / "spheric2_water.off";
  water.fill = "volume";
  water.spacing = 0.00877;
  t0 = std::chrono::steady_clock::now();
  const SampledBody fluid = sample_body(water);
  const double t_volume = seconds_since(t0);
  std::printf("volume:  %ld fluid particles (dx = %.5f m) in %.3f s\n",
              static_cast<long>(fluid.positions.rows()), water.spacing, t_volume);

  // fill the tank minus the obstacle's boundary particles: points_far_from on 1e6 x 1e6
  t0 = std::chrono::steady_clock::now();
  const Eigen::VectorXi keep = points_far_from(fluid.positions, walls.positions, 0.5 * water.spacing);
  std::printf("points_far_from: %ld of %ld fluid points kept (vs %ld boundary points) in %.3f s\n",
              static_cast<long>(keep.size()), static_cast<long>(fluid.positions.rows()),
              static_cast<long>(walls.positions.rows()), seconds_since(t0));
  (void)t_surface;

  // curved geometry: closed cylinder (256 triangles, R = 0.25 m, H = 0.5 m)
  BodyRequest cyl;
  cyl.mesh = dir / "cylinder.off";
  cyl.fill = "volume";
  cyl.spacing = 0.0046;  // volume 0.0982 m^3 -> ~1e6 points
  t0 = std::chrono::steady_clock::now();
  const SampledBody cfill = sample_body(cyl);
  std::printf("volume:  %ld fluid particles in the cylinder (dx = %.5f m) in %.3f s\n",
              static_cast<long>(cfill.positions.rows()), cyl.spacing, seconds_since(t0));
  cyl.fill = "surface";
  cyl.spacing = 0.0022;  // area 1.178 m^2 -> ~2.4e5 particles, most on the curved side (dart throwing)
  t0 = std::chrono::steady_clock::now();
  const SampledBody csurf = sample_body(cyl);
  std::printf("surface: %ld boundary particles on the cylinder (1 layer, dx = %.5f m) in %.3f s\n",
              static_cast<long>(csurf.positions.rows()), cyl.spacing, seconds_since(t0));
  return 0;
}
