// Quantities of a study (study/quantities.hpp) and the ablation verdict on them (study/ablation.hpp): the rounding
// floor of a vector's components, so that a component that is zero by symmetry decides nothing.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "study/ablation.hpp"
#include "study/quantities.hpp"

namespace vs = varsph::study;

namespace {

// A wall force probe on 11 samples over [0, 1]: Fx = fx (1 + t / 10) and Fy = rounding of size fy (zero by symmetry,
// as on a periodic channel's wall) whose sign pattern changes from run to run.
vs::LevelRun force_run(double fx, double fy, int pattern) {
  vs::LevelRun r;
  r.child.exit_code = 0;
  r.probes.columns = {"time", "Fx_w", "Fy_w"};
  std::vector<double> t, x, y;
  for (int i = 0; i <= 10; ++i) {
    t.push_back(0.1 * i);
    x.push_back(fx * (1 + 0.01 * i));
    y.push_back(fy * double((i + pattern) % 3 - 1));
  }
  r.probes.data = {t, x, y};
  return r;
}

const vs::Quantity& find(const std::vector<vs::Quantity>& qs, const std::string& name) {
  for (const auto& q : qs)
    if (q.name == name) return q;
  throw std::runtime_error("no quantity " + name);
}

}  // namespace

TEST(Quantities, VectorComponentsAreRecognisedByName) {
  EXPECT_TRUE(vs::vector_components("Fx_body1", "Fy_body1"));
  EXPECT_TRUE(vs::vector_components("momentum_x", "momentum_z"));
  EXPECT_FALSE(vs::vector_components("p_y030", "p_y060"));
  EXPECT_FALSE(vs::vector_components("Fx_body1", "Fx_body2"));
  EXPECT_FALSE(vs::vector_components("Fx_body1", "Fx_body1"));
  EXPECT_FALSE(vs::vector_components("Fx_w", "Fx_wall"));
}

TEST(Quantities, RoundingInAZeroComponentIsNoChangeAndDecidesNoAblation) {
  // Fx converges as h^2 to 1 N at h = 0.1, 0.05, 0.025; Fy is round-off of 1e-14 N with a new pattern each level
  const std::vector<double> h = {0.1, 0.05, 0.025};
  std::vector<vs::LevelRun> runs;
  for (int k = 0; k < 3; ++k) runs.push_back(force_run(1 + h[k] * h[k], 1e-14 * (k + 1), k));
  vs::AnalysisInput in;
  for (const auto& r : runs) in.levels.push_back(&r);
  in.refined = h;
  in.windows = {{0.0, 1.0}};
  const auto qs = vs::analyse(in);
  for (const char* n : {"Fy_w.mean[0:1]", "Fy_w.end[0:1]", "Fy_w.l2[0:1]"}) {
    const auto& q = find(qs, n);
    EXPECT_GE(q.noise, 1e-9) << n << ": the floor is set by |Fx| ~ 1 N, not by Fy's own 1e-14 N";
    EXPECT_TRUE(q.est.trusted()) << n << ": rounding must not read as oscillating or diverging convergence";
  }
  EXPECT_LT(find(qs, "Fx_w.mean[0:1]").noise, 1e-8);

  // a variant that changes only Fy's rounding: not needed; one that moves Fx by 10 %: essential
  vs::AblationResult same;
  same.run = force_run(1 + h[2] * h[2], 7e-14, 1);
  vs::judge_ablation(same, runs[2], qs, 2, vs::Norm::L2);
  EXPECT_EQ(same.verdict, "not needed at this resolution") << same.reason;
  vs::AblationResult moved;
  moved.run = force_run(1.1 * (1 + h[2] * h[2]), 1e-14, 2);
  vs::judge_ablation(moved, runs[2], qs, 2, vs::Norm::L2);
  EXPECT_EQ(moved.verdict, "essential") << moved.reason;
  EXPECT_NE(moved.reason.find("Fx_w"), std::string::npos) << moved.reason;
}
