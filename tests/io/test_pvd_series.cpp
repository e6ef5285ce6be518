// .pvd frame times: rounded to the output interval where only summation drift separates them from it,
// written as the shortest decimal and read back to the same double (issue 17 point 3).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "io/pvd_series.hpp"

namespace fs = std::filesystem;
using varsph::io::frame_time_label;
using varsph::io::PvdSeries;

namespace {
std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// t after n steps of dt, summed as the solver does (time_ += dt_)
double summed(double dt, long n) {
  double t = 0;
  for (long k = 0; k < n; ++k) t += dt;
  return t;
}
}  // namespace

TEST(FrameTimeLabel, SummedTimesRoundToTheDecimalMultipleOfTheInterval) {
  const double t = summed(1e-4, 3000);  // the drifted 0.3 s frame of dt = 1e-4
  ASSERT_NE(t, 0.3);                     // the drift this fixes
  EXPECT_EQ(frame_time_label(t, 0.02), 0.3);
  for (long k = 0; k <= 50; ++k) {  // every frame of the default scene, 0 .. 1 s every 0.02 s
    const double label = frame_time_label(summed(1e-4, 200 * k), 0.02);
    EXPECT_EQ(label, std::stod(std::to_string(k * 2) + "e-2")) << "frame " << k;
  }
}

TEST(FrameTimeLabel, TimesOffTheGridKeepTheirExactValue) {
  EXPECT_EQ(frame_time_label(0.3051, 0.02), 0.3051);          // a failure frame between two outputs
  EXPECT_EQ(frame_time_label(0.3 + 2e-9, 0.02), 0.3 + 2e-9);  // beyond the drift tolerance
  EXPECT_EQ(frame_time_label(0.123, 0.0), 0.123);             // no interval: nothing to round to
  EXPECT_EQ(frame_time_label(0.0, 0.02), 0.0);
}

TEST(PvdSeries, WritesShortestDecimalsThatReadBackExactly) {
  const fs::path dir = fs::temp_directory_path() / ("varsph_pvd_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // increasing (add() replaces everything at or after a time, as a restart does)
  const double times[] = {0.0, frame_time_label(summed(1e-4, 3000), 0.02), 1.0 / 3.0, 7 * 0.1};
  {
    PvdSeries pvd(dir / "x.pvd");
    int k = 0;
    for (double t : times) pvd.add(t, "frames/x_00000" + std::to_string(k++) + ".vtu");
  }
  const std::string text = read_text(dir / "x.pvd");
  EXPECT_NE(text.find("timestep=\"0.3\""), std::string::npos) << text;
  EXPECT_NE(text.find("timestep=\"0.7000000000000001\""), std::string::npos) << text;  // 7 * 0.1, not rounded
  EXPECT_NE(text.find("timestep=\"0.3333333333333333\""), std::string::npos) << text;
  EXPECT_EQ(text.find("0.29999999999"), std::string::npos) << text;
  PvdSeries back(dir / "x.pvd");
  back.load();
  ASSERT_EQ(back.size(), 4u);
  // re-written from what was read: byte-identical, i.e. every time read back to the same double
  back.write();
  EXPECT_EQ(read_text(dir / "x.pvd"), text);
  fs::remove_all(dir);
}

// Lean frames (issue 35): a frame's static walls are part 1 of its time step; read back and re-written
// unchanged (a restart keeps them), and a frame without static walls has no part 1 line.
TEST(PvdSeries, StaticWallsArePartOneOfTheirTimeStep) {
  const fs::path dir = fs::temp_directory_path() / ("varsph_pvd_static_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  {
    PvdSeries pvd(dir / "x.pvd");
    pvd.add(0.0, "frames/x_000000.vtu", "frames/x_static_000000.vtu");
    pvd.add(0.1, "frames/x_000001.vtu", "frames/x_static_000000.vtu");
    pvd.add(0.2, "frames/x_000002.vtu");
  }
  const std::string text = read_text(dir / "x.pvd");
  EXPECT_NE(text.find("<DataSet timestep=\"0.1\" group=\"\" part=\"1\" file=\"frames/x_static_000000.vtu\"/>"),
            std::string::npos) << text;
  EXPECT_EQ(text.find("timestep=\"0.2\" group=\"\" part=\"1\""), std::string::npos) << text;
  PvdSeries back(dir / "x.pvd");
  back.load();
  EXPECT_EQ(back.size(), 3u);  // time steps, not DataSet lines
  back.write();
  EXPECT_EQ(read_text(dir / "x.pvd"), text);
  fs::remove_all(dir);
}
