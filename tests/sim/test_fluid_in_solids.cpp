// A fixed solid placed in the water (a boundary block or ball, `"kind": "boundary"`) takes the fluid's place:
// no fluid particle is left inside it. The block is sampled only `layers` deep and the ball on a lattice of
// its own (a point at its centre), half a spacing off the fluid's, so the 0.5 dx clearance rule alone kept
// the fluid inside them: the Schaefer-Turek cylinder (pipelines/open) held 88 fluid particles.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

#include <nlohmann/json.hpp>

#include "test_support.hpp"

using namespace varsph;

namespace {

using nlohmann::json;

// fluid box [0, 1] x [0, 0.8] at dx = 0.01 (8000 particles, centres at (i + 1/2) dx), one solid in it
json scene_with(const json& solid) {
  return {{"name", "solid"}, {"setup", "paper"}, {"dimension", 2},
          {"domain", {{"min", {-0.1, -0.1}}, {"max", {1.1, 1.0}}}},
          {"particles", {{"spacing", 0.01}}}, {"gravity", {0, -9.81}},
          {"bodies", {{{"kind", "fluid"}, {"shape", "box"}, {"min", {0, 0}}, {"max", {1.0, 0.8}}}, solid}},
          {"integrator", {{"type", "verlet"}, {"dt", 1e-4}}}, {"time", {{"end", 0.01}}}};
}

// the fluid count `varsph sample` reports
long sampled_fluid(const std::string& name, const json& scene, std::string* output) {
  const auto dir = test::scratch_dir(name);
  std::ofstream(dir / "scene.json") << scene.dump(1);
  std::filesystem::remove_all(dir / "out");
  const auto r = test::run_command(test::varsph_exe().string() + " sample " + (dir / "scene.json").string() +
                                   " -o " + (dir / "out").string());
  *output = r.output;
  if (r.exit_code != 0) return -1;
  std::smatch m;
  if (!std::regex_search(r.output, m, std::regex("particles +([0-9]+) fluid"))) return -1;
  return std::stol(m[1]);
}

}  // namespace

TEST(FluidInSolids, ABoundaryBlockInTheWaterHoldsNoFluid) {
  // block [0.4, 0.6] x [0.3, 0.5], two layers deep: 20 x 20 fluid lattice points inside it, all removed;
  // none outside (the nearest outside fluid centre is dx/2 from the block's face, a spacing from its particles)
  std::string out;
  const long n = sampled_fluid("solid_block", scene_with({{"kind", "boundary"}, {"shape", "box"},
                                                         {"min", {0.4, 0.3}}, {"max", {0.6, 0.5}}, {"layers", 2}}),
                               &out);
  EXPECT_EQ(n, 8000 - 400) << out;
}

TEST(FluidInSolids, ABoundaryBallOffTheFluidLatticeHoldsNoFluid) {
  // a disc R = 0.05 on a lattice of its own (a particle at its centre c, off the fluid's lattice): the fluid
  // within R goes, and the fluid outside it closer than min_boundary_distance (0.5 dx) to a disc particle
  const double cx = 0.503, cy = 0.651, R = 0.05, dx = 0.01;
  long removed = 0, within_r = 0;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 80; ++j) {
      const double x = (i + 0.5) * dx, y = (j + 0.5) * dx;
      bool near = std::hypot(x - cx, y - cy) < R;
      within_r += near;
      for (int a = -6; a <= 6 && !near; ++a)
        for (int b = -6; b <= 6 && !near; ++b)
          near = std::hypot(a * dx, b * dx) <= R + 1e-9 * dx && std::hypot(x - cx - a * dx, y - cy - b * dx) < 0.5 * dx;
      removed += near;
    }
  ASSERT_GT(within_r, 70);  // about pi R^2 / dx^2 = 79; the clearance rule alone removed none of them
  std::string out;
  const long n = sampled_fluid("solid_ball", scene_with({{"kind", "boundary"}, {"shape", "sphere"},
                                                        {"center", {cx, cy}}, {"radius", R}}), &out);
  EXPECT_EQ(n, 8000 - removed) << out;
}

TEST(FluidInSolids, ABoundaryBallOnTheFluidLatticeLeavesNoGap) {
  // centred on a fluid lattice point: the disc takes exactly the fluid points within R, and the fluid right
  // outside it (a spacing from the disc's particles) stays
  const double cx = 0.505, cy = 0.405, R = 0.05, dx = 0.01;
  long within_r = 0;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 80; ++j) within_r += std::hypot((i + 0.5) * dx - cx, (j + 0.5) * dx - cy) <= R + 1e-9 * dx;
  std::string out;
  const long n = sampled_fluid("solid_ball_on", scene_with({{"kind", "boundary"}, {"shape", "sphere"},
                                                           {"center", {cx, cy}}, {"radius", R}}), &out);
  EXPECT_EQ(n, 8000 - within_r) << out;
}
