// Levels of a study (study/level_plan.hpp) and ablation variants (study/ablation.hpp) on the repository's
// scenes: what each level's run is given, how many particles it has, and which variants a scene allows.
#include <gtest/gtest.h>

#include <cmath>

#include "study/ablation.hpp"
#include "scene/scene.hpp"
#include "study/level_plan.hpp"
#include "test_support.hpp"

namespace vs = varsph::study;
using varsph::test::source_dir;

namespace {
vs::StudyOptions options(const std::string& scene, vs::Refine r) {
  vs::StudyOptions o;
  o.scenes = {source_dir() / scene};
  o.refine = r;
  return o;
}
bool contains(const std::vector<std::string>& v, const std::string& s) {
  for (const auto& x : v)
    if (x == s) return true;
  return false;
}
}  // namespace

TEST(LevelPlan, BothRefinesSpacingAndKeepsTheCflNumber) {
  // hydrostatic tank: 0.4 x 0.3 m at dx 0.01 (40 x 30 fluid), CFL 0.2
  auto o = options("pipelines/validation/hydrostatic_tank.json", vs::Refine::Both);
  const auto p = vs::plan_levels(o, 3, 2.0);
  ASSERT_EQ(p.levels.size(), 3u);
  EXPECT_NEAR(p.levels[2].dx, 0.0025, 1e-15);
  EXPECT_NEAR(p.levels[2].h, 1.2 * 0.0025, 1e-15);
  for (const auto& l : p.levels) EXPECT_NEAR(*l.cfl, 0.2, 1e-15);
  EXPECT_EQ(p.levels[0].fluid, 1200u);
  EXPECT_EQ(p.levels[2].fluid, 16u * 1200u);
  EXPECT_NEAR(p.levels[2].fluid_mass, p.levels[0].fluid_mass, 1e-9 * p.levels[0].fluid_mass);  // same water
  EXPECT_DOUBLE_EQ(p.formal_order, 2.0);
  EXPECT_NEAR(p.levels[1].refined, 0.005, 1e-15);
  EXPECT_FALSE(p.levels[0].probe_set.empty());  // a front probe and a force probe on the tank were added
}

TEST(LevelPlan, DtRefinesTheStepOnly) {
  auto o = options("pipelines/dam_break_2d_paper.json", vs::Refine::Dt);
  const auto p = vs::plan_levels(o, 3, 2.0);
  for (const auto& l : p.levels) EXPECT_NEAR(l.dx, 0.005, 1e-15);
  EXPECT_NEAR(*p.levels[2].dt, 2.5e-5, 1e-18);
  EXPECT_NEAR(p.levels[1].refined, 5e-5, 1e-18);
  EXPECT_EQ(p.levels[0].fluid, 1682u);
  EXPECT_DOUBLE_EQ(p.formal_order, 2.0);  // verlet
}

TEST(LevelPlan, DxHoldsEveryLevelAtTheFinestStep) {
  auto o = options("pipelines/dam_break_2d_paper.json", vs::Refine::Dx);
  const auto p = vs::plan_levels(o, 3, 2.0);
  for (const auto& l : p.levels) EXPECT_NEAR(*l.dt, 2.5e-5, 1e-18);
  EXPECT_NEAR(p.levels[2].dx, 0.00125, 1e-15);
  EXPECT_EQ(p.levels[1].fluid, 4u * 1682u);
}

TEST(LevelPlan, CoarsestSpacingAndSqrt2Ratio) {
  auto o = options("pipelines/dam_break_2d_paper.json", vs::Refine::Both);
  o.coarsest_dx = 0.01;
  const auto p = vs::plan_levels(o, 2, std::sqrt(2.0));
  EXPECT_NEAR(p.levels[0].dx, 0.01, 1e-15);
  EXPECT_NEAR(*p.levels[0].dt, 2e-4, 1e-15);  // the scene's dt/dx kept
  EXPECT_NEAR(p.levels[1].dx, 0.01 / std::sqrt(2.0), 1e-15);
}

TEST(LevelPlan, ScaledCountsForBudgetCandidates) {
  auto o = options("pipelines/validation/hydrostatic_tank.json", vs::Refine::Both);
  const auto sampled = vs::plan_levels(o, 2, 2.0);
  const auto scaled = vs::plan_levels(o, 2, 2.0, &sampled.levels[0]);
  EXPECT_EQ(scaled.levels[1].fluid, sampled.levels[1].fluid);
  EXPECT_NEAR(double(scaled.levels[1].boundary), double(sampled.levels[1].boundary),
              0.1 * double(sampled.levels[1].boundary));
}

TEST(LevelPlan, PointsBodyCannotBeRefinedInDx) {
  auto o = options("pipelines/validation/taylor_green_dx0.02.json", vs::Refine::Both);
  try {
    vs::plan_levels(o, 3, 2.0);
    FAIL() << "expected an InputError";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bodies.0.shape"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("one scene per level"), std::string::npos) << e.what();
  }
}

TEST(LevelPlan, PredictionScalesParticleSteps) {
  auto o = options("pipelines/dam_break_2d_paper.json", vs::Refine::Both);
  const auto p = vs::plan_levels(o, 2, 2.0);
  vs::Measured m;
  m.wall = 10;
  m.cpu = 20;
  m.steps = 10000;
  m.fluid = 1682;
  m.boundary = 358;
  m.rss_mb = 60;
  m.baseline_rss_mb = 40;
  m.t_end = 1;
  m.dt_estimate = 1e-4;
  const auto pr = vs::predict_cost(m, p.levels[1]);
  EXPECT_NEAR(pr.steps, 20000, 1e-9);
  EXPECT_NEAR(pr.wall, 10 * 8.0 * double(p.levels[1].fluid) / (4.0 * 1682), 1e-9);
  EXPECT_NEAR(pr.cpu, 2 * pr.wall, 1e-9);
  EXPECT_GT(pr.rss_mb, 60);
}

TEST(Ablation, VariantsOfTheDamBreak) {
  auto o = options("pipelines/dam_break_2d_paper.json", vs::Refine::Both);
  const auto p = vs::plan_levels(o, 2, 2.0);
  std::vector<std::string> notes;
  const auto v = vs::ablation_variants(
      {"physics.artificial_viscosity", "physics.xsph", "gravity", "boundary.model", "integrator.alpha=0.5"},
      p.levels[0], notes);
  ASSERT_GE(v.size(), 4u);
  EXPECT_EQ(v[0].label, "without physics.artificial_viscosity");
  EXPECT_TRUE(contains(v[0].sets, "physics.artificial_viscosity=null"));
  EXPECT_EQ(v[1].label, "with physics.xsph (its defaults)");
  EXPECT_EQ(v[2].label, "without gravity");
  EXPECT_TRUE(contains(v[2].sets, "gravity=[0,0]"));
  // c0 and the wall's D are held at the base's values (they follow gravity when "auto")
  bool pinned = false;
  for (const auto& s : v[2].sets) pinned = pinned || s.rfind("fluid.c0=23.84", 0) == 0;
  EXPECT_TRUE(pinned);
  int models = 0;
  for (const auto& x : v) models += x.term == "boundary.model";
  EXPECT_GE(models, 1);
  EXPECT_LE(models, 3);
  EXPECT_EQ(v.back().label, "integrator.alpha = 0.5");
}

TEST(Ablation, ItemsThatCannotBeVariantsAreInputErrors) {
  auto o = options("pipelines/dam_break_2d_paper.json", vs::Refine::Both);
  const auto p = vs::plan_levels(o, 2, 2.0);
  std::vector<std::string> notes;
  EXPECT_THROW(vs::ablation_variants({"kernel.type"}, p.levels[0], notes), std::runtime_error);
  EXPECT_THROW(vs::ablation_variants({"integrator.alpha"}, p.levels[0], notes), std::runtime_error);  // verlet
  EXPECT_THROW(vs::ablation_variants({"physics.laminar_viscosity"}, p.levels[0], notes), std::runtime_error);
  EXPECT_THROW(vs::ablation_variants({"boundary.model=nonsense"}, p.levels[0], notes), std::runtime_error);
}

TEST(Ablation, NullSetRemovesATerm) {
  // `--set KEY=null` is the same as the file omitting KEY (CONTRACT.md): the ablations switch terms off with it
  const auto dam = source_dir() / "pipelines/dam_break_2d_paper.json";
  const auto with = varsph::scene::parse_scene(dam);
  const auto without = varsph::scene::parse_scene(dam, {"physics.artificial_viscosity=null"});
  EXPECT_TRUE(with.artificial_viscosity);
  EXPECT_FALSE(without.artificial_viscosity);
  EXPECT_TRUE(with.resolved.contains(nlohmann::json::json_pointer("/physics/artificial_viscosity")));
  EXPECT_FALSE(without.resolved.contains(nlohmann::json::json_pointer("/physics/artificial_viscosity")));
}
