// The toolbox scene keys: defaults written to the resolved scene, ranges and combinations rejected with
// the key named (InputError).
#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "scene/scene.hpp"

using namespace varsph;
using nlohmann::json;

namespace {

json base() {
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
    scene::parse_scene_json(base(), "bad.json", overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ToolboxScene, NothingNamedMeansEverythingOff) {
  const auto s = scene::parse_scene_json(base(), "ok.json");
  EXPECT_FALSE(s.laminar_viscosity);
  EXPECT_EQ(s.xsph_eps, 0);
  EXPECT_FALSE(s.damping);
  EXPECT_EQ(s.gravity_ramp, 0);
  EXPECT_EQ(s.density_diffusion, "none");
  EXPECT_EQ(s.tensile, "none");
  EXPECT_EQ(s.boundary_model, "repulsive");
  EXPECT_EQ(s.body_force, (std::vector<double>{0, 0}));
}

TEST(ToolboxScene, DefaultsAreFilledInAndResolved) {
  const auto s = scene::parse_scene_json(
      base(), "ok.json",
      {"physics.xsph={}", "physics.density_diffusion={}", "physics.tensile_instability={}",
       "physics.damping={\"mu\": 2}", "physics.gravity_ramp={\"duration\": 0.1}", "boundary.model=dummy_adami",
       "physics.laminar_viscosity={\"nu\": 1e-6}"});
  EXPECT_EQ(s.xsph_eps, 0.5);
  EXPECT_EQ(s.density_diffusion, "molteni");
  EXPECT_EQ(s.diffusion_delta, 0.1);
  EXPECT_EQ(s.tensile, "artificial_stress");
  EXPECT_EQ(s.as_eps, 0.2);
  EXPECT_EQ(s.damping_mu, 2);
  EXPECT_TRUE(std::isinf(s.damping_until));
  EXPECT_EQ(s.gravity_ramp, 0.1);
  EXPECT_EQ(s.wall_slip, "no_slip");
  EXPECT_EQ(s.nu, 1e-6);
  EXPECT_EQ(s.resolved["physics"]["xsph"]["epsilon"], 0.5);
  EXPECT_EQ(s.resolved["boundary"]["slip"], "no_slip");
}

TEST(ToolboxScene, BadValuesNameTheirKey) {
  EXPECT_NE(error_of({"physics.xsph={\"epsilon\": 1.5}"}).find("physics.xsph.epsilon"), std::string::npos);
  EXPECT_NE(error_of({"physics.laminar_viscosity={}"}).find("physics.laminar_viscosity.nu"), std::string::npos);
  EXPECT_NE(error_of({"physics.laminar_viscosity=3"}).find("physics.laminar_viscosity"), std::string::npos);
  EXPECT_NE(error_of({"physics.density_diffusion={\"type\": \"fancy\"}"}).find("physics.density_diffusion.type"),
            std::string::npos);
  EXPECT_NE(error_of({"physics.density=summation", "physics.density_diffusion={}"}).find("physics.density_diffusion"),
            std::string::npos);
  EXPECT_NE(error_of({"boundary.model=ghost"}).find("boundary.model"), std::string::npos);
  EXPECT_NE(error_of({"boundary.model=dummy_adami", "boundary.slip=sticky"}).find("boundary.slip"), std::string::npos);
  EXPECT_NE(error_of({"physics.damping={\"mu\": 1, \"typo\": 2}"}).find("physics.damping.typo"), std::string::npos);
  EXPECT_NE(error_of({"physics.gravity_ramp={\"duration\": 0}"}).find("physics.gravity_ramp.duration"),
            std::string::npos);
}
