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
  return {{"name", "solid"}, {"dimension", 2},
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
  // a disc R = 0.05 centred off the fluid's lattice: its surface sits at R + dx/2 (half a spacing beyond its
  // outermost particles); the fluid inside that circle goes, the fluid outside stays
  const double cx = 0.503, cy = 0.651, R = 0.05, dx = 0.01;
  long inside = 0;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 80; ++j)
      inside += std::hypot((i + 0.5) * dx - cx, (j + 0.5) * dx - cy) < R + 0.5 * dx;
  ASSERT_GT(inside, 90);  // about pi (R + dx/2)^2 / dx^2 = 95
  std::string out;
  const long n = sampled_fluid("solid_ball", scene_with({{"kind", "boundary"}, {"shape", "sphere"},
                                                        {"center", {cx, cy}}, {"radius", R}}), &out);
  EXPECT_EQ(n, 8000 - inside) << out;
}
