// `varsph study` through the binary: bad input is exit 2 with a message naming what is wrong, before any run
// and in under a second; --help describes every option.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>

#include "test_support.hpp"

using namespace varsph::test;

namespace {
std::string study(const std::string& args) { return varsph_exe().string() + " study " + args; }
std::string scene(const std::string& s) { return (source_dir() / s).string(); }

void expect_input_error(const std::string& args, const std::string& needle) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = run_command(study(args));
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
  EXPECT_NE(r.output.find(needle), std::string::npos) << args << "\n" << r.output;
  EXPECT_LT(s, 5.0) << args;  // under a second on an idle machine; generous for a loaded CI runner
}
}  // namespace

TEST(StudyCommand, HelpListsTheOptions) {
  const auto r = run_command(study("--help"));
  EXPECT_EQ(r.exit_code, 0);
  for (const char* opt : {"--refine", "--levels", "--ratio", "--threads", "--budget", "--ablate", "--tolerance",
                          "--window", "--norm", "--reuse", "--dx"})
    EXPECT_NE(r.output.find(opt), std::string::npos) << opt;
}

TEST(StudyCommand, BadInputIsExitTwoBeforeAnyRun) {
  const auto out = scratch_dir("study_bad_input");
  const std::string dam = scene("pipelines/dam_break_2d_paper.json");
  expect_input_error("/nonexistent/scene.json -o " + (out / "a").string(), "/nonexistent/scene.json");
  expect_input_error(dam + " --refine space -o " + (out / "a").string(), "--refine");
  expect_input_error(dam + " --ratio 1 -o " + (out / "a").string(), "--ratio");
  expect_input_error(dam + " --levels 1 -o " + (out / "a").string(), "--levels");
  expect_input_error(dam + " --window 0.5:0.2 -o " + (out / "a").string(), "--window");
  expect_input_error(dam + " --norm l3 -o " + (out / "a").string(), "--norm");
  expect_input_error(dam + " --tolerance abc -o " + (out / "a").string(), "--tolerance");
  expect_input_error(dam + " --ablate kernel.type -o " + (out / "a").string(), "--ablate kernel.type");
  expect_input_error(dam + " --ablate physics.laminar_viscosity -o " + (out / "a").string(), "nu");
  expect_input_error(dam + " --set integrator.type=nonsense -o " + (out / "a").string(), "integrator.type");
  expect_input_error(scene("pipelines/validation/taylor_green_dx0.02.json") + " -o " + (out / "a").string(),
                     "bodies.0.shape");
  EXPECT_FALSE(std::filesystem::exists(out / "a")) << "nothing may be written before the input is validated";
  // an existing non-empty study directory is refused without --overwrite / --reuse, and left as it was
  std::filesystem::create_directories(out / "b");
  std::ofstream(out / "b" / "keep.txt") << "x";
  expect_input_error(dam + " -o " + (out / "b").string(), "not empty");
  EXPECT_TRUE(std::filesystem::exists(out / "b" / "keep.txt"));
}
