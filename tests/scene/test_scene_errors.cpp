// Bad scenes give InputError (exit 2) naming the file and the key or line:column and what was expected.
#include <gtest/gtest.h>

#include <fstream>

#include "core/errors.hpp"
#include "scene/scene.hpp"
#include "sim/scene_summary.hpp"
#include "test_support.hpp"

using namespace varsph;
using nlohmann::json;

namespace {

json base_scene() {
  return json::parse(R"({
    "name": "t", "setup": "paper", "dimension": 2,
    "domain": {"min": [-0.1, -0.1], "max": [1, 1]},
    "particles": {"spacing": 0.02},
    "gravity": [0, -9.81],
    "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0], "max": [0.2, 0.2]},
               {"kind": "boundary", "shape": "tank", "min": [0, 0], "max": [0.5, 0.5]}],
    "integrator": {"dt": 1e-4},
    "time": {"end": 0.01}
  })");
}

struct Case {
  std::string what;
  std::function<void(json&)> edit;
  std::vector<std::string> overrides;
  std::string expected;  // substring of the message
};

std::string error_of(json j, const std::vector<std::string>& overrides = {}) {
  try {
    const auto s = scene::parse_scene_json(std::move(j), "bad.json", overrides);
    (void)describe_scene(s);  // builds particles too (bodies outside the domain, ...)
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(SceneErrors, EachMalformedInputNamesItsKey) {
  const std::vector<Case> cases = {
      {"unknown key", [](json& j) { j["integrator"]["foo"] = 1; }, {}, "unknown key 'integrator.foo'"},
      {"negative spacing", [](json& j) { j["particles"]["spacing"] = -0.01; }, {}, "'particles.spacing'"},
      {"no fluid", [](json& j) { j["bodies"].erase(0); }, {}, "\"kind\": \"fluid\""},
      {"neither dt nor cfl", [](json& j) { j["integrator"].erase("dt"); }, {}, "integrator.dt [s] or integrator.cfl"},
      {"empty domain", [](json& j) { j["domain"]["max"] = json::array({-0.2, 1}); }, {}, "'domain.max'"},
      {"wrong type", [](json& j) { j["dimension"] = "two"; }, {}, "'dimension': expected an integer"},
      {"missing name", [](json& j) { j.erase("name"); }, {}, "'name'"},
      {"alpha out of range", [](json& j) { j["integrator"]["alpha"] = 1.5; }, {}, "'integrator.alpha'"},
      {"unknown kernel", [](json& j) { j["kernel"]["type"] = "quintic"; }, {}, "'kernel.type': expected one of"},
      {"vector length", [](json& j) { j["bodies"][0]["min"] = json::array({0, 0, 0}); }, {}, "'bodies.0.min'"},
      {"body outside domain", [](json& j) { j["bodies"][0]["max"] = json::array({2.0, 0.2}); }, {}, "bodies.0"},
      {"--set unknown key", [](json&) {}, {"integrator.fixed_point.tolerence=1e-3"}, "'integrator.fixed_point.tolerence'"},
      {"--set index out of range", [](json&) {}, {"bodies.5.kind=fluid"}, "index '5' is out of range"},
      {"--set wrong type", [](json&) {}, {"time.end=soon"}, "'time.end'"},
      {"both dt and cfl", [](json& j) { j["integrator"]["cfl"] = 0.2; }, {}, "only one of"},
      {"zero end time", [](json& j) { j["time"]["end"] = 0; }, {}, "'time.end'"},
      {"verlet_dsph needs continuity",
       [](json& j) { j["integrator"]["type"] = "verlet_dsph"; j["physics"]["density"] = "summation"; }, {},
       "'physics.density'"},
      {"verlet_dsph euler_every", [](json& j) { j["integrator"]["type"] = "verlet_dsph"; j["integrator"]["euler_every"] = 0; },
       {}, "'integrator.euler_every'"},
      // issue 35: unknown keys at every level with the closest valid key; --set errors name the argument
      {"misspelt top-level block", [](json& j) { j["particle"] = j["particles"]; j.erase("particles"); }, {},
       "unknown key 'particle' (did you mean 'particles'?"},
      {"misspelt key in a block", [](json& j) { j["kernel"]["typ"] = "wendland_c2"; }, {},
       "unknown key 'kernel.typ' (did you mean 'kernel.type'?)"},
      {"misspelt required body key", [](json& j) { j["bodies"][0]["shap"] = "box"; j["bodies"][0].erase("shape"); }, {},
       "unknown key 'bodies.0.shap' (did you mean 'bodies.0.shape'?"},
      {"misspelt physics term", [](json& j) { j["physics"]["artifical_viscosity"] = json::object({{"alpha", 0.1}}); }, {},
       "unknown key 'physics.artifical_viscosity' (did you mean 'physics.artificial_viscosity'?)"},
      {"--set misspelt block", [](json&) {}, {"particle.spacing=0.01"},
       "--set 'particle.spacing=0.01' (scene bad.json): unknown key 'particle' (did you mean 'particles'?)"},
      {"--set misspelt key", [](json&) {}, {"integrator.fixed_point.tolerence=1e-3"},
       "--set 'integrator.fixed_point.tolerence=1e-3' (scene bad.json): unknown key 'integrator.fixed_point.tolerence' "
       "(did you mean 'integrator.fixed_point.tolerance'?)"},
      {"--set bad value", [](json&) {}, {"time.end=soon"}, "--set 'time.end=soon' (scene bad.json): key 'time.end'"},
      {"--set index", [](json&) {}, {"bodies.5.kind=fluid"}, "--set 'bodies.5.kind=fluid' (scene bad.json): index '5'"},
      {"no guess for a far key", [](json& j) { j["zzzzzz"] = 1; }, {}, "unknown key 'zzzzzz'; not part"},
      {"verlet_dsph with riemann",
       [](json& j) { j["integrator"]["type"] = "verlet_dsph"; j["physics"] = {{"density", "continuity"}, {"riemann", json::object()}}; },
       {}, "'physics.riemann'"},
  };
  for (const auto& c : cases) {
    json j = base_scene();
    c.edit(j);
    const std::string msg = error_of(j, c.overrides);
    EXPECT_NE(msg.find(c.expected), std::string::npos) << c.what << ": got \"" << msg << "\"";
    EXPECT_NE(msg.find("bad.json"), std::string::npos) << c.what << ": message must name the file: " << msg;
  }
}

TEST(SceneErrors, ValidSceneParsesAndSetCreatesKnownKeys) {
  EXPECT_EQ(error_of(base_scene()), "");
  const auto s = scene::parse_scene_json(base_scene(), "ok.json", {"integrator.alpha=0.25", "kernel.type=\"cubic_spline\"",
                                                                   "kernel.h_over_dx=1.5"});
  EXPECT_DOUBLE_EQ(s.alpha, 0.25);
  EXPECT_EQ(s.kernel, kernels::KernelType::CubicSpline);
  EXPECT_DOUBLE_EQ(s.h, 0.03);
  // the resolved scene lists defaults
  EXPECT_EQ(s.resolved["integrator"]["fixed_point"]["max_iterations"], 50);
}

TEST(SceneErrors, CommandLineExitCodesAndSyntaxErrorPosition) {
  const auto dir = test::scratch_dir("scene_errors_cli");
  const auto bad = dir / "syntax.json";
  std::ofstream(bad) << "{\n  \"name\": \"x\",\n  \"dimension\": 2,,\n}\n";
  auto r = test::run_command(test::varsph_exe().string() + " run " + bad.string() + " -o " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("syntax.json:3:"), std::string::npos) << r.output;

  const auto good = dir / "good.json";
  std::ofstream(good) << base_scene().dump(2);
  r = test::run_command(test::varsph_exe().string() + " info " + good.string() + " --set physics.nonsense=1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("physics.nonsense"), std::string::npos) << r.output;

  r = test::run_command(test::varsph_exe().string() + " run " + (dir / "missing.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("missing.json"), std::string::npos) << r.output;

  // an existing non-empty output directory is refused without --overwrite
  std::filesystem::create_directories(dir / "busy");
  std::ofstream(dir / "busy" / "keep.txt") << "x";
  r = test::run_command(test::varsph_exe().string() + " run " + good.string() + " -o " + (dir / "busy").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "busy" / "keep.txt"));

  r = test::run_command(test::varsph_exe().string() + " run --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("--restart"), std::string::npos);
}
