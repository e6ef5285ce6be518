// Sanity rules on finite but absurd physics inputs (docs/scene.md "Sanity checks") and the particle
// budget (particles.max_count): errors name the file, the key, the rule and the value; warnings are
// listed by `varsph info`; every scene the project ships passes without an error.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/errors.hpp"
#include "scene/sanity.hpp"
#include "scene/scene.hpp"
#include "sim/particle_budget.hpp"
#include "test_support.hpp"

using namespace varsph;
using nlohmann::json;
namespace fs = std::filesystem;

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

std::string error_of(const std::vector<std::string>& overrides) {
  try {
    const auto s = scene::parse_scene_json(base_scene(), "s.json", overrides);
    check_particle_budget(s);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::vector<std::string> warnings_of(const std::vector<std::string>& overrides) {
  return scene::check_sanity(scene::parse_scene_json(base_scene(), "s.json", overrides));
}

bool has(const std::vector<std::string>& w, const std::string& text) {
  for (const auto& x : w)
    if (x.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(Sanity, ValuesThatCannotBeMeantAreErrorsNamingKeyRuleAndValue) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"gravity=[0,-1e30]"}, "s.json: key 'gravity': |g| = 1e+30 m/s^2 is more than 100000 m/s^2"},
      {{"fluid.rho0=1e30"}, "key 'fluid.rho0': rho0 = 1e+30 kg/m^3 is outside [0.001, 1e+06]"},
      {{"fluid.rho0=1e-5"}, "key 'fluid.rho0': rho0 = 1e-05 kg/m^3 is outside"},
      {{"fluid.c0=1e9"}, "key 'fluid.c0': c0 = 1e+09 m/s is faster than light"},
      {{"domain.max=[1e30,1]", "bodies.0.max=[1e30,0.2]"}, "key 'domain.max': the domain reaches 1e+30 m on axis 0"},
      // c0 = 10 sqrt(2 g 0.2) = 19.81 m/s (auto rule), h = 0.024 m: C = 165.08
      {{"integrator.dt=0.2"}, "key 'integrator.dt': dt = 0.2 s is 165.0"},
      {{"time.end=1e7"}, "key 'time.end': time.end = 1e+07 s needs 1e+11 steps"},
      {{"output.every=1e-10"}, "key 'output.every': output.every = 1e-10 s writes 1e+08 frames"},
  };
  for (const auto& [set, expected] : cases) {
    const std::string m = error_of(set);
    EXPECT_NE(m.find(expected), std::string::npos) << set[0] << ": " << m;
  }
  EXPECT_NE(error_of({"integrator.dt=0.2"}).find("more than 100 x"), std::string::npos);
  // the dt rule is relative to h/c0: C = 82.5 is only a warning
  EXPECT_EQ(error_of({"integrator.dt=0.1"}), "");
}

TEST(Sanity, UnusualValuesAreWarnings) {
  EXPECT_TRUE(warnings_of({}).empty()) << warnings_of({})[0];
  EXPECT_TRUE(has(warnings_of({"gravity=[0,-200]"}), "gravity: |g| = 200 m/s^2 is more than 100 m/s^2"));
  EXPECT_TRUE(has(warnings_of({"fluid.rho0=0.1"}), "fluid.rho0: rho0 = 0.1 kg/m^3 is outside [0.5, 30000]"));
  EXPECT_TRUE(has(warnings_of({"fluid.c0=5"}), "fluid.c0: c0 = 5 m/s is less than 10 x the expected flow speed 1.98"));
  EXPECT_TRUE(has(warnings_of({"fluid.c0=2e4"}), "above the sound speed of any liquid"));
  EXPECT_TRUE(has(warnings_of({"integrator.dt=0.003"}), "integrator.dt: dt = 0.003 s is 2.4"));
  EXPECT_TRUE(has(warnings_of({"domain.min=[-100,-100]", "domain.max=[100,100]"}), "domain: the domain's diagonal"));
  EXPECT_TRUE(has(warnings_of({"time.end=1e5"}), "time.end: time.end = 100000 s needs 1e+09 steps"));
  // a non-dimensional scene (rho0 = 1, g = 1, c0 = 10) is not unusual
  EXPECT_TRUE(warnings_of({"fluid.rho0=1", "gravity=[0,-1]", "fluid.c0=10"}).empty());
}

// With a given c0 the scene may name its flow scales: a deep, still tank whose c0 is chosen for a slow body is not
// warned of a dam-break speed it never reaches, but is told how much its column is squeezed.
TEST(Sanity, NamedReferenceScalesInformTheMachWarningOfAGivenC0) {
  // base scene: H = 0.2 m, sqrt(2 g H) = 1.981 m/s; c0 = 5 m/s is Mach 0.40 on it
  EXPECT_TRUE(has(warnings_of({"fluid.c0=5"}), "1.98"));
  // a named reference speed of 0.3 m/s: Mach 0.06, no Mach warning; g H / c0^2 = 9.81 0.2 / 25 = 7.85 %
  const auto w = warnings_of({"fluid.c0=5", "fluid.reference_speed=0.3"});
  EXPECT_FALSE(has(w, "less than 10 x")) << (w.empty() ? "" : w[0]);
  EXPECT_TRUE(has(w, "fluid.c0: c0 = 5 m/s compresses the fluid's 0.2 m column by g H / c0^2 = 7.848 %")) << w.size();
  // a stiff c0 with the same named speed: neither warning (g H / c0^2 = 0.0785 %)
  EXPECT_TRUE(warnings_of({"fluid.c0=50", "fluid.reference_speed=0.3"}).empty());
  // a named speed above 10 % of c0 warns, naming the reference speed
  EXPECT_TRUE(has(warnings_of({"fluid.c0=50", "fluid.reference_speed=6"}),
                  "expected flow speed 6 m/s (max of fluid.reference_speed and the initial velocities): Mach 0.12"));
  // a named reference height sets the dam-break speed: sqrt(2 g 2) = 6.264 m/s against c0 = 50
  EXPECT_TRUE(has(warnings_of({"fluid.c0=50", "fluid.reference_height=2"}), "expected flow speed 6.26"));
  // the keys keep their ranges with a given c0
  EXPECT_NE(error_of({"fluid.c0=5", "fluid.reference_speed=-1"}).find("fluid.reference_speed"), std::string::npos);
}

// A wall 4 spacings thick written with 6 decimals of a spacing that is not round (0.054603 m at dx = 0.0136508 m)
// is 3.99997 spacings: the sampler fits 3 layers and leaves a hole of one spacing (found in a generated flume whose
// fluid drained through its bed). The check names the body and the length that was meant.
TEST(Sanity, ABoxAHairShortOfWholeSpacingsIsNamed) {
  const auto w = warnings_of({"particles.spacing=0.013650843396894256", "bodies.1.shape=\"box\"",
                              "bodies.1.min=[0,-0.054603]", "bodies.1.max=[0.5,0]"});
  EXPECT_TRUE(has(w, "bodies.1.max: the box is 3.99997 spacings long on axis 1: it holds 3 particles across")) << w.size();
  EXPECT_TRUE(has(w, "4 spacings (min = -0.0546034 or max = 3.7"));
  // the same wall written with enough digits: no warning
  EXPECT_TRUE(warnings_of({"particles.spacing=0.013650843396894256", "bodies.1.shape=\"box\"",
                           "bodies.1.min=[0,-0.054603373587577]", "bodies.1.max=[0.5,0]"}).empty());
}

TEST(Sanity, InfoListsTheWarningsAndRunRefusesErrorsWithExit2) {
  const auto dir = test::scratch_dir("sanity_cli");
  const auto scene = dir / "s.json";
  std::ofstream(scene) << base_scene().dump();
  const std::string exe = test::varsph_exe().string();
  auto r = test::run_command(exe + " info " + scene.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warnings           none"), std::string::npos) << r.output;
  r = test::run_command(exe + " info " + scene.string() + " --set 'gravity=[0,-200]'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning            gravity: |g| = 200 m/s^2"), std::string::npos) << r.output;
  r = test::run_command(exe + " run " + scene.string() + " -o " + (dir / "run").string() + " --set 'gravity=[0,-1e30]'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("key 'gravity'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "run" / "t.pvd"));
}

TEST(ParticleBudget, EstimateBeforeSamplingAgainstMaxCount) {
  // fluid box 0.2 x 0.2 at dx 0.02: 100 particles; tank 0.5 x 0.5 with 1 layer, open top: 27 x 26 - 25 x 25 = 77
  const auto s = scene::parse_scene_json(base_scene(), "s.json");
  EXPECT_EQ(estimate_body_particles(s, 0), 100);
  EXPECT_EQ(estimate_body_particles(s, 1), 77);
  EXPECT_EQ(error_of({"particles.max_count=177"}), "");
  const std::string m = error_of({"particles.max_count=176"});
  EXPECT_NE(m.find("s.json: bodies.1 (tank) would produce about 77 particles at dx = 0.02 m, 177 with the bodies "
                   "before it, more than particles.max_count = 176"), std::string::npos) << m;
  // the default limit (1e7) refuses a 10 m x 10 m box at dx = 1 mm before anything is allocated
  const std::string big = error_of({"domain.max=[11,11]", "bodies.0.max=[10,10]", "particles.spacing=0.001"});
  EXPECT_NE(big.find("bodies.0 (box) would produce about 1e+08 particles"), std::string::npos) << big;
  // through the binary: exit 2, and a higher limit lets info build it
  const auto dir = test::scratch_dir("budget_cli");
  std::ofstream(dir / "s.json") << base_scene().dump();
  const std::string exe = test::varsph_exe().string();
  auto r = test::run_command(exe + " sample " + (dir / "s.json").string() + " -o " + (dir / "out").string() +
                             " --set particles.max_count=150");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("particles.max_count = 150"), std::string::npos) << r.output;
}

TEST(Sanity, EveryShippedSceneParsesWithoutError) {
  int n = 0;
  for (const auto* sub : {"pipelines", "pipelines/validation", "pipelines/paper_alpha_study"})
    for (const auto& e : fs::directory_iterator(test::source_dir() / sub)) {
      if (e.path().extension() != ".json") continue;
      const auto s = scene::parse_scene(e.path());
      for (const auto& w : scene::check_sanity(s)) std::printf("[ warning  ] %s: %s\n", e.path().filename().c_str(), w.c_str());
      ++n;
    }
  EXPECT_GT(n, 10);
}
