// CFL-adaptive dt: acoustic, force and viscous limits with their own coefficients.
#include <gtest/gtest.h>

#include <cmath>

#include "core/errors.hpp"
#include "integrators/time_step_control.hpp"
#include "scene/json_reader.hpp"
#include "scene/scene.hpp"
#include "sim/simulation.hpp"
#include "test_support.hpp"

using namespace varsph;
using nlohmann::json;

namespace {

json dam_break_with_cfl(const std::string& integrator, double cfl) {
  json j = scene::read_json_file(test::source_dir() / "pipelines" / "dam_break_2d_paper.json");
  j["integrator"] = {{"type", integrator}, {"cfl", cfl}};
  return j;
}

}  // namespace

TEST(Cfl, DefaultCriteriaAreTheFoundationRule) {
  for (const char* type : {"verlet", "symplectic_euler", "predictor_corrector", "rk4"}) {
    Simulation<2> sim(scene::parse_scene_json(dam_break_with_cfl(type, 0.25), "cfl.json"));
    for (int k = 0; k < 5; ++k) sim.advance();
    const CflLimits L = cfl_limits(sim);
    const double h = sim.scene().h, c0 = sim.scene().c0;
    ASSERT_GT(L.a_max, 0);
    EXPECT_DOUBLE_EQ(L.acoustic, 0.25 * h / (c0 + L.v_max)) << type;
    EXPECT_DOUBLE_EQ(L.force, 0.25 * std::sqrt(h / L.a_max)) << type;
    // artificial viscosity alpha = 0.1: nu = alpha c0 h / 8 in 2D, far from binding
    EXPECT_DOUBLE_EQ(L.nu, 0.1 * c0 * h / 8);
    EXPECT_DOUBLE_EQ(L.viscous, 0.125 * h * h / L.nu);
    EXPECT_EQ(sim.cfl_dt(), L.dt());
    EXPECT_EQ(sim.choose_dt(), L.dt());
    EXPECT_GT(sim.time(), 0);
  }
}

TEST(Cfl, EachCriterionCanBind) {
  json j = dam_break_with_cfl("rk4", 0.2);
  j["integrator"]["cfl_criteria"] = {{"force", 1e-4}};
  {
    Simulation<2> sim(scene::parse_scene_json(j, "cfl.json"));
    sim.advance();  // a is known after the first step
    const CflLimits L = cfl_limits(sim);
    EXPECT_STREQ(L.binding(), "force");
    EXPECT_DOUBLE_EQ(sim.cfl_dt(), 1e-4 * std::sqrt(sim.scene().h / L.a_max));
  }
  j["integrator"]["cfl_criteria"] = {{"viscous", 1e-3}};
  j["physics"]["artificial_viscosity"]["alpha"] = 1.0;
  {
    Simulation<2> sim(scene::parse_scene_json(j, "cfl.json"));
    const CflLimits L = cfl_limits(sim);
    const double h = sim.scene().h, c0 = sim.scene().c0;
    EXPECT_STREQ(L.binding(), "viscous");
    EXPECT_DOUBLE_EQ(sim.cfl_dt(), 1e-3 * h * h / (1.0 * c0 * h / 8));
    EXPECT_DOUBLE_EQ(sim.cfl_dt(), 1e-3 * 8 * h / c0);
  }
  j["integrator"]["cfl_criteria"] = {{"acoustic", 0.05}};
  {
    Simulation<2> sim(scene::parse_scene_json(j, "cfl.json"));
    EXPECT_STREQ(cfl_limits(sim).binding(), "acoustic");
    EXPECT_DOUBLE_EQ(sim.cfl_dt(), 0.05 * sim.scene().h / sim.scene().c0);  // at rest
  }
}

TEST(Cfl, AdaptiveDtFollowsTheFlowAndCriteriaNeedCfl) {
  Simulation<2> sim(scene::parse_scene_json(dam_break_with_cfl("predictor_corrector", 0.2), "cfl.json"));
  const double dt0 = sim.dt();
  double dt_min = dt0;
  for (int k = 0; k < 200; ++k) {
    sim.advance();
    dt_min = std::min(dt_min, sim.dt());
    EXPECT_GT(sim.dt(), 0);
  }
  EXPECT_LT(dt_min, dt0);  // the column accelerates: v_max grows, dt shrinks
  EXPECT_GT(sim.time(), 150 * dt_min);
  json j = scene::read_json_file(test::source_dir() / "pipelines" / "dam_break_2d_paper.json");
  j["integrator"]["cfl_criteria"] = {{"force", 0.1}};  // with a fixed dt: refused
  EXPECT_THROW(scene::parse_scene_json(j, "cfl.json"), InputError);
}
