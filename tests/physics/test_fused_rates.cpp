// The fused continuity + acceleration sweep (FusedRatesPass) gives bitwise the same drho/dt and
// accelerations as the two separate passes, for every wall model, viscosity and density-diffusion
// policy it is compiled for; exact (non-tabulated) kernels keep the separate passes.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "scene/json_reader.hpp"
#include "scene/scene.hpp"
#include "sim/simulation.hpp"
#include "test_support.hpp"

using namespace varsph;

namespace {

struct Rates2 {
  std::vector<Real> drho;
  std::vector<Vec<2>> a;
};

void expect_fused_equals_separate(const std::vector<std::string>& sets, bool no_viscosity = false) {
  std::string what;
  for (const auto& s : sets) what += s + " ";
  const auto file = test::source_dir() / "pipelines" / "dam_break_2d_paper.json";
  nlohmann::json j = scene::read_json_file(file);
  if (no_viscosity) j["physics"].erase("artificial_viscosity");
  // The scalar sweep on both sides: the vectorised sweep covers some passes and not others (laminar
  // viscosity stays scalar), and vector vs scalar agree to round-off, not bitwise (test_simd_sweep).
  setenv("VARSPH_SIMD", "scalar", 1);
  Simulation<2> sim(scene::parse_scene_json(j, file, sets));
  unsetenv("VARSPH_SIMD");
  for (int k = 0; k < 30; ++k) sim.advance();  // moving fluid, densities off rho0, walls updated
  ASSERT_TRUE(sim.rates().fused()) << what;
  const std::size_t n = sim.size();
  Rates2 sep{std::vector<Real>(n, Real(-7)), std::vector<Vec<2>>(n, Vec<2>::Constant(-7))};
  Rates2 fus = sep;
  const auto view = sim.current_view();
  sim.rates().density_rate(sim.grid(), view, sep.drho.data());
  sim.rates().acceleration(sim.grid(), view, sep.a.data());
  sim.rates().density_rate_and_acceleration(sim.grid(), view, fus.drho.data(), fus.a.data());
  EXPECT_EQ(0, std::memcmp(sep.drho.data(), fus.drho.data(), n * sizeof(Real))) << what;
  EXPECT_EQ(0, std::memcmp(sep.a.data(), fus.a.data(), n * sizeof(Vec<2>))) << what;
  // and the sweep computed something: the fluid moves, the density changes
  double max_a = 0, max_drho = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (sim.fields().kind[i] == 0) {
      max_a = std::max(max_a, double(fus.a[i].norm()));
      max_drho = std::max(max_drho, std::abs(double(fus.drho[i])));
    }
  EXPECT_GT(max_a, 1.0) << what;
  EXPECT_GT(max_drho, 1.0) << what;
}

}  // namespace

TEST(FusedRates, RepulsiveWallsArtificialViscosity) { expect_fused_equals_separate({}); }

TEST(FusedRates, DynamicWallsWithFourtakasDiffusion) {
  expect_fused_equals_separate({"boundary.model=\"dynamic\"",
                                "physics.density_diffusion={\"type\": \"fourtakas\", \"delta\": 0.1}"});
}

TEST(FusedRates, DummyWallsLaminarAndArtificialViscosityMolteni) {
  expect_fused_equals_separate({"boundary.model=\"dummy_adami\"", "physics.laminar_viscosity={\"nu\": 1e-3}",
                                "physics.density_diffusion={\"type\": \"molteni\", \"delta\": 0.1}"});
}

TEST(FusedRates, SoftRepulsiveWallsWithoutViscosity) {
  expect_fused_equals_separate({"boundary.model=\"soft_repulsive\""}, true);
}

TEST(FusedRates, ExactKernelsKeepTheSeparatePasses) {
  Simulation<2> sim(scene::parse_scene(test::source_dir() / "pipelines" / "dam_break_2d_paper.json",
                                       {"kernel.tabulated=false"}));
  EXPECT_FALSE(sim.rates().fused());
}
