// Placing a mesh (issue 35, point 7): the documented transform order (docs/scene.md "Placing a mesh"), the
// per-body counts and boxes `varsph sample` prints to check it, and the messages a misplaced mesh gets.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include <nlohmann/json.hpp>

#include "test_support.hpp"

using namespace varsph;

namespace {

using nlohmann::json;

// the unit cube [0, 1]^3 as an OFF file (outward-facing triangles)
void write_cube(const std::filesystem::path& path) {
  std::ofstream f(path);
  f << "OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
       "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 2 3 7\n3 2 7 6\n3 1 2 6\n3 1 6 5\n3 0 4 7\n"
       "3 0 7 3\n";
}

json cube_scene(const json& transform) {
  return {{"name", "cube"}, {"setup", "paper"}, {"dimension", 3},
          {"domain", {{"min", {-3, -3, -3}}, {"max", {3, 3, 3}}}},
          {"particles", {{"spacing", 0.1}}}, {"gravity", {0, 0, -9.81}},
          {"bodies", {{{"kind", "fluid"}, {"shape", "box"}, {"min", {-2.5, -2.5, -2.5}}, {"max", {-2.3, -2.3, -2.3}}},
                      {{"kind", "boundary"}, {"mesh", "meshes/cube.off"}, {"transform", transform}}}},
          {"integrator", {{"dt", 1e-4}}}, {"time", {{"end", 0.01}}}};
}

test::CommandResult sample(const std::filesystem::path& dir, const json& scene) {
  std::ofstream(dir / "scene.json") << scene.dump(1);
  std::filesystem::remove_all(dir / "out");
  return test::run_command(test::varsph_exe().string() + " sample " + (dir / "scene.json").string() + " -o " +
                           (dir / "out").string());
}

// the box of body `b`'s particle centres from `varsph sample`'s report: {x0, y0, z0, x1, y1, z1}
std::vector<double> body_box(const std::string& report, int b) {
  const std::regex re("body " + std::to_string(b) +
                      " +[^\\n]*: ([0-9]+) particles, centres in \\[([^,]+), ([^,]+), ([^\\]]+)\\] \\.\\. "
                      "\\[([^,]+), ([^,]+), ([^\\]]+)\\] m");
  std::smatch m;
  if (!std::regex_search(report, m, re)) return {};
  std::vector<double> box;
  for (int k = 2; k <= 7; ++k) box.push_back(std::stod(m[k]));
  return box;
}

}  // namespace

TEST(PlacingMeshes, ScaleThenRotateXYZThenTranslateAsDocumented) {
  const auto dir = test::scratch_dir("placing_order");
  std::filesystem::create_directories(dir / "meshes");
  write_cube(dir / "meshes" / "cube.off");
  // scale x by 2: [0,2]x[0,1]x[0,1]; about z by 90 deg: (x, y) -> (-y, x): [-1,0]x[0,2]x[0,1];
  // translate +1 in x: [0,1]x[0,2]x[0,1]. Translating first, or rotating before scaling, gives another box.
  const auto r = sample(dir, cube_scene({{"scale", {2, 1, 1}}, {"rotate_deg", {0, 0, 90}}, {"translate", {1, 0, 0}}}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto box = body_box(r.output, 1);
  ASSERT_EQ(box.size(), 6u) << r.output;
  const std::vector<double> expect = {0, 0, 0, 1, 2, 1};
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(box[k], expect[k], 0.06) << "axis " << k % 3 << "\n" << r.output;
  // x then y then z: scale [1,2,3] gives [0,1]x[0,2]x[0,3]; 90 deg about x, (x, y, z) -> (x, -z, y):
  // [0,1]x[-3,0]x[0,2]; then 90 deg about z, (x, y) -> (-y, x): [0,3]x[0,1]x[0,2]. About z first, then x,
  // would give [-2,0]x[-3,0]x[0,1].
  const auto r2 = sample(dir, cube_scene({{"scale", {1, 2, 3}}, {"rotate_deg", {90, 0, 90}}}));
  ASSERT_EQ(r2.exit_code, 0) << r2.output;
  const auto box2 = body_box(r2.output, 1);
  ASSERT_EQ(box2.size(), 6u) << r2.output;
  const std::vector<double> expect2 = {0, 0, 0, 3, 1, 2};
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(box2[k], expect2[k], 0.06) << "axis " << k % 3 << "\n" << r2.output;
}

TEST(PlacingMeshes, SamplePrintsEveryBodyWithItsCountAndBox) {
  const auto dir = test::scratch_dir("placing_report");
  const auto r = test::run_command(test::varsph_exe().string() + " sample " +
                                   (test::source_dir() / "pipelines" / "hydrostatic_2d.json").string() + " -o " +
                                   (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // the fluid box [0, 0.4] x [0, 0.3] at dx = 0.01: 40 x 30 particles, centres 0.005 .. 0.395 / 0.295
  EXPECT_NE(r.output.find("body 0       fluid box: 1200 particles, centres in [0.005, 0.005] .. [0.395, 0.295] m"),
            std::string::npos) << r.output;
  EXPECT_NE(r.output.find("body 1       boundary tank: "), std::string::npos) << r.output;
}

TEST(PlacingMeshes, MessagesNameTheResolvedPathAndTheClosestKey) {
  const auto dir = test::scratch_dir("placing_errors");
  // a relative mesh path that is not there: the absolute path looked for and the folder it is relative to
  auto r = sample(dir, cube_scene({{"scale", 1}}));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  const auto looked = std::filesystem::weakly_canonical(dir / "meshes" / "cube.off").string();
  EXPECT_NE(r.output.find("bodies.1.mesh: file 'meshes/cube.off' not found: looked for " + looked),
            std::string::npos) << r.output;
  EXPECT_NE(r.output.find("taken from the folder of the scene file"), std::string::npos) << r.output;
  std::filesystem::create_directories(dir / "meshes");
  write_cube(dir / "meshes" / "cube.off");
  r = sample(dir, cube_scene({{"rotate", {0, 0, 90}}}));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("unknown key 'rotate' (did you mean 'rotate_deg'?)"), std::string::npos) << r.output;
  r = sample(dir, cube_scene({{"scale", 2}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}}));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("either {matrix} or {scale, rotate_deg, translate}"), std::string::npos) << r.output;
}
