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

TEST(FluidInSolids, AClosedMeshObstacleHoldsNoFluidAndAMeshTankKeepsIt) {
  // the unit cube as an OFF file, shifted off the fluid's lattice; fluid box [-0.5, 1.5]^3 at dx = 0.1: the
  // 10 x 10 x 10 fluid points inside the cube go (the clearance rule alone kept about 670 of them). The same
  // mesh as a tank (layer_side "outside", the default) holds its fluid: nothing is removed as "inside".
  const auto dir = test::scratch_dir("solid_mesh");
  std::filesystem::create_directories(dir / "meshes");
  std::ofstream(dir / "meshes" / "cube.off")
      << "OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n3 0 2 1\n3 0 3 2\n3 4 5 6\n"
         "3 4 6 7\n3 0 1 5\n3 0 5 4\n3 2 3 7\n3 2 7 6\n3 1 2 6\n3 1 6 5\n3 0 4 7\n3 0 7 3\n";
  const auto scene = [&](const std::string& side) {
    json mesh = {{"kind", "boundary"}, {"mesh", "meshes/cube.off"}, {"layers", 2},
                 {"transform", {{"translate", {0.033, 0.047, 0.021}}}}};
    if (!side.empty()) mesh["layer_side"] = side;
    return json{{"name", "mesh_solid"}, {"setup", "paper"}, {"dimension", 3},
                {"domain", {{"min", {-1, -1, -1}}, {"max", {2, 2, 2}}}}, {"particles", {{"spacing", 0.1}}},
                {"gravity", {0, 0, -9.81}},
                {"bodies", {{{"kind", "fluid"}, {"shape", "box"}, {"min", {-0.5, -0.5, -0.5}}, {"max", {1.5, 1.5, 1.5}}},
                            mesh}},
                {"integrator", {{"type", "verlet"}, {"dt", 1e-4}}}, {"time", {{"end", 0.01}}}};
  };
  const auto sample = [&](const json& j) {
    std::ofstream(dir / "scene.json") << j.dump(1);
    std::filesystem::remove_all(dir / "out");
    return test::run_command(test::varsph_exe().string() + " sample " + (dir / "scene.json").string() + " -o " +
                             (dir / "out").string());
  };
  auto r = sample(scene("inside"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("removed 1000 fluid particles inside solid bodies"), std::string::npos) << r.output;
  r = sample(scene(""));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("inside solid bodies"), std::string::npos) << r.output;
}
