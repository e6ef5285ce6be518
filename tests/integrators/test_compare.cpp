// `varsph compare` (seed eq. 70, CONTRACT.md): deviation.csv and deviation.pvd, exit 2 for runs that
// cannot be matched.
#include <gtest/gtest.h>

#include <fstream>

#include "test_support.hpp"
#include "variational_cases.hpp"

using namespace varsph;

namespace {
std::filesystem::path write_run(const std::filesystem::path& dir, const std::string& name, int n, double alpha,
                                const std::string& type, double every, double t_end = 0.01) {
  auto j = test::lattice_scene(n, 0.5, true, alpha, type, "continuity", 2e-4);
  j["name"] = name;
  j["time"] = {{"end", t_end}};
  j["output"] = {{"every", every}, {"precision", "float64"}};
  std::ofstream(dir / (name + ".json")) << j.dump();
  const auto r = test::run_command(test::varsph_exe().string() + " run " + (dir / (name + ".json")).string() +
                                   " -o " + (dir / name).string() + " --threads 1 --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return dir / name;
}
std::string exe() { return test::varsph_exe().string(); }
}  // namespace

TEST(Compare, DeviationOfTwoRunsMatchedByTimeAndId) {
  const auto dir = test::scratch_dir("compare_ok");
  const auto a = write_run(dir, "a", 16, 1.0, "verlet", 0.005);
  const auto b = write_run(dir, "b", 16, 0.5, "variational", 0.0025);
  const auto r = test::run_command(exe() + " compare " + a.string() + " " + b.string() + " -o " + (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string csv = test::read_text(dir / "out" / "deviation.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "time,D_max,D_mean,D_rms,matched,only_a,only_b");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4) << csv;  // header + t = 0, 0.005, 0.01
  EXPECT_NE(csv.find("\n0,0,0,0,256,0,0\n"), std::string::npos) << csv;  // same initial state, 16 x 16 matched
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "deviation.pvd"));
  const std::string vtu = test::read_text(dir / "out" / "frames" / "deviation_000001.vtu");
  EXPECT_NE(vtu.find("Name=\"deviation\""), std::string::npos);
  EXPECT_NE(vtu.find("Name=\"deviation_magnitude\""), std::string::npos);
  // a run against itself: zero everywhere
  const auto s = test::run_command(exe() + " compare " + a.string() + " " + a.string() + " -o " + (dir / "self").string());
  ASSERT_EQ(s.exit_code, 0) << s.output;
  const std::string self = test::read_text(dir / "self" / "deviation.csv");
  EXPECT_NE(self.find("0.01,0,0,0"), std::string::npos) << self;
}

TEST(Compare, UnmatchableRunsExitWith2) {
  const auto dir = test::scratch_dir("compare_bad");
  const auto a = write_run(dir, "a", 16, 1.0, "verlet", 0.005);
  const auto c = write_run(dir, "c", 20, 1.0, "verlet", 0.005);  // other particle set
  auto r = test::run_command(exe() + " compare " + a.string() + " " + c.string() + " -o " + (dir / "o1").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("particle"), std::string::npos) << r.output;
  const auto d = write_run(dir, "d", 16, 1.0, "verlet", 0.003, 0.009);  // 0, 0.003, 0.006, 0.009
  // drop the t = 0 frame from d's series so that no time is common
  std::string pvd = test::read_text(dir / "d" / "d.pvd");
  const auto p0 = pvd.find("<DataSet timestep=\"0\"");
  ASSERT_NE(p0, std::string::npos) << pvd;
  pvd.erase(p0, pvd.find('\n', p0) - p0 + 1);
  std::ofstream(dir / "d" / "d.pvd") << pvd;
  r = test::run_command(exe() + " compare " + a.string() + " " + (dir / "d").string() + " -o " + (dir / "o2").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("common"), std::string::npos) << r.output;
}
