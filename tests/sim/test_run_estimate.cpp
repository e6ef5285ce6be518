// Estimates before a run (issue 35, point 4): `varsph info` prints particles per body, memory, steps, wall
// time from a short calibration and disk, warns past the user's limits, and answers quickly from a coarser
// copy for a scene too large to sample.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>

#include "test_support.hpp"

using namespace varsph;

namespace {

double number_after(const std::string& text, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(pattern))) return -1;
  return std::stod(m[1]);
}

std::string info(const std::string& args) {
  const auto r = test::run_command(test::varsph_exe().string() + " info " + args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return r.output;
}

const std::string kScene = (test::source_dir() / "pipelines" / "hydrostatic_2d.json").string();

}  // namespace

TEST(RunEstimate, InfoPrintsBodiesStepsDiskAndAFrameOfTheSizeEstimated) {
  // fixed dt: steps = time.end / dt exactly; 0.02 s at 1e-4 s, frames every 0.01 s: 3 frames
  const std::string set = " --set integrator.cfl=null --set integrator.dt=1e-4 --set time.end=0.02 --set output.every=0.01";
  const std::string out = info(kScene + set + " --threads 1");
  EXPECT_NE(out.find("body 0              fluid box: 1200 particles"), std::string::npos) << out;
  EXPECT_NE(out.find("estimate steps      200 (fixed dt)"), std::string::npos) << out;
  EXPECT_NE(out.find("for 3 frames ("), std::string::npos) << out;
  const double kb_each = number_after(out, "frames \\(([0-9.]+) kB each");
  const double ms = number_after(out, "\\(([0-9.e+-]+) ms per step measured on 1 thread");
  ASSERT_GT(kb_each, 0) << out;
  ASSERT_GT(ms, 0) << out;
  // the run: its frames are the size estimated (within the 3 digits printed), its steps take about the
  // time measured (a loaded machine: within a factor 4)
  const auto dir = test::scratch_dir("run_estimate");
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = test::run_command(test::varsph_exe().string() + " run " + kScene + set + " --threads 1 --quiet -o " +
                                   (dir / "run").string() + " --overwrite");
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const double bytes = double(std::filesystem::file_size(dir / "run" / "frames" / "hydrostatic_2d_000001.vtu"));
  EXPECT_NEAR(bytes / 1e3, kb_each, 0.01 * kb_each) << out;
  EXPECT_LT(200 * ms / 1e3, 4 * wall) << "estimated " << 200 * ms / 1e3 << " s, the run took " << wall << " s";
}

TEST(RunEstimate, LimitsTheUserSetsGiveWarnings) {
  const std::string out = info(kScene + " --max-memory 1e-9 --max-disk 1e-9 --max-hours 1e-9");
  EXPECT_NE(out.find("warning            estimate: memory"), std::string::npos) << out;
  EXPECT_NE(out.find("(--max-memory)"), std::string::npos) << out;
  EXPECT_NE(out.find("warning            estimate: disk"), std::string::npos) << out;
  EXPECT_NE(out.find("warning            estimate: wall time"), std::string::npos) << out;
  EXPECT_EQ(info(kScene).find("warning            estimate"), std::string::npos) << "no limit passed by default";
}

TEST(RunEstimate, AFrameMostlyOfStaticWallsPointsToLeanFrames) {
  // the tutorial's torus tank: 9246 of 9946 particles are static walls
  const std::string scene = (test::source_dir() / "docs" / "tutorial" / "torus_3d.json").string();
  std::string out = info(scene + " --set 'output.static_boundary=\"every_frame\"'");
  EXPECT_NE(out.find("static walls are 93 % of every frame: output.static_boundary = \"once\" writes them once"),
            std::string::npos) << out;
  // and at the start of the run, before any frame is written
  const auto dir = test::scratch_dir("run_estimate_static");
  const auto r = test::run_command(test::varsph_exe().string() + " run " + scene +
                                   " --set 'output.static_boundary=\"every_frame\"' --set time.end=0.001 --threads 1 -o " +
                                   (dir / "run").string() + " --overwrite");
  EXPECT_NE(r.output.find("static walls are 93 % of every frame"), std::string::npos) << r.output;
  out = info(scene);  // it asks for "once" already: said as the static walls' file
  EXPECT_EQ(out.find("static walls are"), std::string::npos) << out;
  EXPECT_NE(out.find("+ the static walls once"), std::string::npos) << out;
}

TEST(RunEstimate, ATooLargeSceneIsEstimatedFromACoarserCopyQuickly) {
  // at dx = 0.5 mm the tank holds 480,000 fluid particles: not sampled (--calibrate-max 1e5 by default)
  const auto t0 = std::chrono::steady_clock::now();
  const std::string out = info(kScene + " --set particles.spacing=0.0005 --threads 1");
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_NE(out.find("not sampled"), std::string::npos) << out;
  EXPECT_NE(out.find("body 0              fluid box: 480000 particles (estimate)"), std::string::npos) << out;
  EXPECT_NE(out.find("scaled from a copy at"), std::string::npos) << out;
  EXPECT_LT(wall, 10.0) << "info took " << wall << " s";
}
