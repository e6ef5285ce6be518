// The `varsph` binary end to end: exact restart, restart refusals, signals, blow-up, I/O failures,
// VTU precision and PVD validity (read back with VTK).
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <cstring>
#include <thread>

#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "io/checkpoint.hpp"
#include "results_scenes.hpp"
#include "test_support.hpp"

using namespace varsph;
namespace fs = std::filesystem;

namespace {

std::string exe() { return test::varsph_exe().string(); }
std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

std::vector<std::string> lines(const fs::path& p) {
  std::vector<std::string> out;
  std::ifstream in(p);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// diagnostics rows without the wall_seconds column (index 14)
std::vector<std::string> diag_without_wall(const fs::path& p) {
  std::vector<std::string> out;
  for (const auto& l : lines(p)) {
    std::vector<std::string> c;
    std::stringstream ss(l);
    for (std::string x; std::getline(ss, x, ',');) c.push_back(x);
    if (c.size() > 14) c.erase(c.begin() + 14);
    std::string j;
    for (const auto& x : c) j += x + ",";
    out.push_back(j);
  }
  return out;
}

// Every .pvd entry names an existing frame VTK can read; the file is complete XML.
void expect_valid_pvd(const fs::path& pvd) {
  const std::string text = test::read_text(pvd);
  ASSERT_NE(text.find("<?xml"), std::string::npos);
  ASSERT_NE(text.find("</VTKFile>"), std::string::npos) << text;
  std::size_t pos = 0;
  while ((pos = text.find("file=\"", pos)) != std::string::npos) {
    pos += 6;
    const std::string f = text.substr(pos, text.find('"', pos) - pos);
    EXPECT_TRUE(fs::exists(pvd.parent_path() / f)) << f;
  }
}

std::string read_file_bytes(const fs::path& p) { return test::read_text(p); }

bool unshare_available() { return test::run_command("unshare -rm true").exit_code == 0; }

}  // namespace

// ------------------------------------------------------------------------------------ exact restart

class Restart : public ::testing::TestWithParam<std::string> {};

// 200 steps straight vs 100 + restart (own directory) + 100, and 100 + restart into a new directory:
// bitwise identical particle arrays at step 200 and byte-identical frames after the restart point.
// Particles are re-sorted by cell every step (the store order changes) in both runs.
TEST_P(Restart, StraightAndRestartedRunsAreBitwiseIdentical) {
  const std::string integrator = GetParam();
  const auto dir = test::scratch_dir("restart_" + integrator);
  const auto scene = test::write_scene(dir, test::tiny_dam_break(integrator));
  const auto straight = dir / "straight", split = dir / "split", other = dir / "other";
  auto r = test::run_command(exe() + " run " + q(scene) + " -o " + q(straight) + " --quiet");
  if (r.exit_code == 2 && r.output.find("not available in this build") != std::string::npos)
    GTEST_SKIP() << "integrator.type = " << integrator << " is not available in this build: " << r.output;
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::run_command(exe() + " run " + q(scene) + " -o " + q(split) + " --quiet --set time.end=0.02");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto ckpt100 = split / "checkpoints" / "step_000000100.h5";
  ASSERT_TRUE(fs::exists(ckpt100));
  fs::copy_file(ckpt100, dir / "c100.h5");
  // restart into the run's own directory (the default -o with --restart)
  r = test::run_command(exe() + " run " + q(scene) + " --restart " + q(ckpt100) + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // and into a new directory
  r = test::run_command(exe() + " run " + q(scene) + " --restart " + q(dir / "c100.h5") + " -o " + q(other) +
                        " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;

  const auto a = io::read_checkpoint(straight / "checkpoints" / "step_000000200.h5");
  for (const fs::path& run : {split, other}) {
    const auto b = io::read_checkpoint(run / "checkpoints" / "step_000000200.h5");
    EXPECT_EQ(a.header.time, b.header.time);
    EXPECT_EQ(a.header.dt, b.header.dt);
    ASSERT_EQ(a.arrays.size(), b.arrays.size());
    for (std::size_t k = 0; k < a.arrays.size(); ++k) {
      EXPECT_EQ(a.arrays[k].name, b.arrays[k].name);
      EXPECT_TRUE(a.arrays[k].bytes == b.arrays[k].bytes) << run << ": field " << a.arrays[k].name << " differs";
    }
    // frames after the restart point (frames 6..10: t = 0.024 .. 0.04) are byte-identical
    for (int k = 6; k <= 10; ++k) {
      char name[64];
      std::snprintf(name, sizeof name, "frames/tiny_%06d.vtu", k);
      ASSERT_TRUE(fs::exists(run / name)) << run / name;
      EXPECT_TRUE(read_file_bytes(straight / name) == read_file_bytes(run / name)) << run / name << " differs";
    }
  }
  // the own directory looks exactly like the straight run's: pvd, diagnostics (but wall time), probes
  EXPECT_EQ(test::read_text(straight / "tiny.pvd"), test::read_text(split / "tiny.pvd"));
  EXPECT_EQ(diag_without_wall(straight / "diagnostics.csv"), diag_without_wall(split / "diagnostics.csv"));
  EXPECT_EQ(test::read_text(straight / "probes.csv"), test::read_text(split / "probes.csv"));
  expect_valid_pvd(split / "tiny.pvd");
  // the last two checkpoints are kept
  const auto kept = io::list_checkpoints(split / "checkpoints");
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept.back().first, 200);
}

// "variational" runs once the variational integrator is merged; until then it is skipped with the
// build's "not available in this build" message (and only then).
INSTANTIATE_TEST_SUITE_P(Integrators, Restart, ::testing::Values("verlet", "variational"));

TEST(Restart, EveryStepsCheckpointsAndRateChangesAreAccepted) {
  const auto dir = test::scratch_dir("restart_every");
  const auto scene = test::write_scene(dir, test::tiny_dam_break());
  auto r = test::run_command(exe() + " run " + q(scene) + " -o " + q(dir / "run") +
                             " --quiet --set checkpoint.every_steps=30 --set time.end=0.02");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto kept = io::list_checkpoints(dir / "run" / "checkpoints");
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[0].first, 90);
  EXPECT_EQ(kept[1].first, 100);
  r = test::run_command(exe() + " run " + q(scene) + " --restart " + q(kept[0].second) +
                        " --quiet --set output.every=0.002 --set time.end=0.03");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(dir / "run" / "checkpoints" / "step_000000100.h5")) << "a replaced future checkpoint";
  expect_valid_pvd(dir / "run" / "tiny.pvd");
}

// ------------------------------------------------------------------------------ restart refusals

TEST(Restart, BadCheckpointsGiveExit2AndOverwriteNothing) {
  const auto dir = test::scratch_dir("restart_refusals");
  const auto scene = test::write_scene(dir, test::tiny_dam_break());
  const auto run = dir / "run";
  auto r = test::run_command(exe() + " run " + q(scene) + " -o " + q(run) + " --quiet --set time.end=0.004");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto good = run / "checkpoints" / "step_000000020.h5";
  ASSERT_TRUE(fs::exists(good));
  const auto snapshot = [&] {
    std::map<std::string, std::string> m;
    for (const auto& e : fs::recursive_directory_iterator(run))
      if (e.is_regular_file()) m[e.path().string()] = test::read_text(e.path());
    return m;
  };
  const auto before = snapshot();

  const auto bad = dir / "bad";
  fs::create_directories(bad / "checkpoints");
  const auto size = fs::file_size(good);
  fs::copy_file(good, bad / "checkpoints" / "truncated.h5");
  fs::resize_file(bad / "checkpoints" / "truncated.h5", size / 3);
  fs::copy_file(good, bad / "checkpoints" / "corrupted.h5");
  {
    // garbage over bytes the file uses (chunk data or metadata, both checksummed) from the middle on: an
    // HDF5 file can hold zero padding, which no checksum covers and whose place moves with the header size
    const std::string bytes = test::read_text(good);
    std::size_t at = size / 2;
    while (at < bytes.size() && bytes[at] == '\0') ++at;
    ASSERT_LT(at + 21, bytes.size());
    std::fstream f(bad / "checkpoints" / "corrupted.h5", std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(std::streamoff(at));
    f.write("garbagegarbagegarbage", 21);
  }
  struct Case {
    std::string what, cmd, expect;
  };
  auto scene3d = test::tiny_dam_break();
  scene3d["dimension"] = 3;
  scene3d["domain"] = {{"min", {-0.1, -0.1, -0.1}}, {"max", {0.5, 0.4, 0.1}}};
  scene3d["gravity"] = {0, -9.81, 0};
  scene3d["bodies"] = nlohmann::json::parse(R"([{"kind": "fluid", "shape": "box", "min": [0, 0, 0], "max": [0.1, 0.2, 0.04]},
    {"kind": "boundary", "shape": "box", "min": [0.3, 0, 0], "max": [0.34, 0.04, 0.04]}])");
  scene3d["probes"] = nlohmann::json::array();
  const auto s3 = test::write_scene(dir, scene3d, "scene3d.json");
  const std::vector<Case> cases = {
      {"truncated", exe() + " run " + q(scene) + " --restart " + q(bad / "checkpoints" / "truncated.h5") + " -o " + q(run), "truncated"},
      {"corrupted", exe() + " run " + q(scene) + " --restart " + q(bad / "checkpoints" / "corrupted.h5") + " -o " + q(run), "checkpoint"},
      {"other dimension", exe() + " run " + q(s3) + " --restart " + q(good) + " -o " + q(run), "2D"},
      {"other particle count", exe() + " run " + q(scene) + " --restart " + q(good) + " --set particles.spacing=0.025", "particles.spacing"},
      {"other physics", exe() + " run " + q(scene) + " --restart " + q(good) + " --set fluid.c0=25", "fluid.c0"},
      {"missing", exe() + " run " + q(scene) + " --restart " + q(dir / "nope.h5") + " -o " + q(run), "not found"},
  };
  for (const auto& c : cases) {
    r = test::run_command(c.cmd);
    EXPECT_EQ(r.exit_code, 2) << c.what << ": " << r.output;
    EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.what << ": " << r.output;
  }
  EXPECT_TRUE(before == snapshot()) << "a refused restart changed the run directory";
}

// ---------------------------------------------------------------------------------------- signals

namespace {

// Starts `varsph run` in the background; returns its pid.
pid_t spawn_run(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<char*> argv;
  std::vector<std::string> a = {exe()};
  a.insert(a.end(), args.begin(), args.end());
  for (auto& s : a) argv.push_back(s.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  pid_t pid = -1;
  if (posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&fa);
  return pid;
}

}  // namespace

class Signals : public ::testing::TestWithParam<int> {};

TEST_P(Signals, StopAfterTheStepWriteACheckpointAndExit130Or143) {
  const int sig = GetParam();
  const auto dir = test::scratch_dir(std::string("signal_") + (sig == SIGINT ? "int" : "term"));
  const auto scene = test::write_scene(dir, test::tiny_dam_break());
  const auto run = dir / "run";
  const pid_t pid = spawn_run({"run", scene.string(), "-o", run.string(), "--set", "time.end=1000", "--set",
                               "output.every=0.002", "--threads", "1"},
                              dir / "log.txt");
  ASSERT_GT(pid, 0);
  // wait for a few frames, checking that the .pvd is valid whenever we look
  const auto t0 = std::chrono::steady_clock::now();
  while (lines(run / "diagnostics.csv").size() < 5) {
    ASSERT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(60)) << "the run did not start";
    if (fs::exists(run / "tiny.pvd")) expect_valid_pvd(run / "tiny.pvd");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_EQ(kill(pid, sig), 0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), sig == SIGINT ? 130 : 143);
  const std::string log = test::read_text(dir / "log.txt");
  EXPECT_NE(log.find(sig == SIGINT ? "stopped by SIGINT" : "stopped by SIGTERM"), std::string::npos) << log;
  const auto kept = io::list_checkpoints(run / "checkpoints");
  ASSERT_FALSE(kept.empty());
  const auto c = io::read_checkpoint(kept.back().second);
  EXPECT_GT(c.header.step, 0);
  EXPECT_NE(log.find(kept.back().second.filename().string()), std::string::npos) << log;
  expect_valid_pvd(run / "tiny.pvd");
  // the pvd's last frame is the state of the checkpoint
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  char name[64];
  std::snprintf(name, sizeof name, "frames/tiny_%06ld.vtu", long(c.header.runner_state.at("frame_index")) - 1);
  reader->SetFileName((run / name).c_str());
  reader->Update();
  EXPECT_EQ(long(reader->GetOutput()->GetFieldData()->GetArray("step")->GetTuple1(0)), c.header.step);
  // and it restarts
  auto r = test::run_command(exe() + " run " + q(scene) + " --restart " + q(kept.back().second) + " --quiet --set time.end=" +
                             std::to_string(c.header.time + 0.002));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  expect_valid_pvd(run / "tiny.pvd");
}

INSTANTIATE_TEST_SUITE_P(IntTerm, Signals, ::testing::Values(SIGINT, SIGTERM));

// --------------------------------------------------------------------------------------- blow-up

TEST(BlowUp, StopsWithExit3AndWritesTheLastGoodFrameAndCheckpoint) {
  const auto dir = test::scratch_dir("blow_up");
  // a time step 20x the acoustic limit: the column explodes within a few steps
  const auto scene = test::write_scene(dir, test::tiny_dam_break());
  const auto run = dir / "run";
  const auto r = test::run_command(exe() + " run " + q(scene) + " -o " + q(run) + " --set integrator.dt=0.004 --set time.end=1");
  ASSERT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("numerical failure at step"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("particle id"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("t = "), std::string::npos) << r.output;
  const auto kept = io::list_checkpoints(run / "checkpoints");
  ASSERT_EQ(kept.size(), 1u);
  const auto c = io::read_checkpoint(kept.back().second);
  const auto at = r.output.find("numerical failure at step ");
  const long bad_step = std::stol(r.output.substr(at + std::strlen("numerical failure at step ")));
  EXPECT_EQ(c.header.step, bad_step - 1) << "the checkpoint is the last good step";
  for (const auto& a : c.arrays)
    if (a.type == ScalarType::Float64)
      for (std::size_t k = 0; k < a.bytes.size() / 8; ++k) {
        double v;
        std::memcpy(&v, a.bytes.data() + 8 * k, 8);
        ASSERT_TRUE(std::isfinite(v)) << a.name;
      }
  expect_valid_pvd(run / "tiny.pvd");
  const std::string json = test::read_text(run / "run.json");
  EXPECT_NE(json.find("\"failed\""), std::string::npos);
  EXPECT_NE(json.find("last_good_copy_seconds"), std::string::npos);
}

// --------------------------------------------------------------------------------------- I/O errors

TEST(IoFailure, UnwritableOutputDirectoryGivesExit4) {
  const auto dir = test::scratch_dir("io_unwritable");
  const auto scene = test::write_scene(dir, test::tiny_dam_break());
  // a path below a non-directory (works without privileges)
  auto r = test::run_command(exe() + " run " + q(scene) + " -o /dev/full/run --quiet");
  EXPECT_EQ(r.exit_code, 4) << r.output;
  if (!unshare_available()) GTEST_SKIP() << "unshare -rm not available: read-only mount case not run";
  // a read-only file system (root ignores permission bits, so chmod would not do)
  fs::create_directories(dir / "ro");
  r = test::run_command("unshare -rm sh -c \"mount -t tmpfs -o ro,size=1m tmpfs " + q(dir / "ro") + " && " + exe() +
                        " run " + q(scene) + " -o " + q(dir / "ro" / "run") + " --quiet\"");
  EXPECT_EQ(r.exit_code, 4) << r.output;
  EXPECT_NE(r.output.find("I/O error"), std::string::npos) << r.output;
}

TEST(IoFailure, DiskFullGivesExit4AndLeavesNoPartialFile) {
  if (!unshare_available()) GTEST_SKIP() << "unshare -rm not available: cannot mount a small tmpfs";
  const auto dir = test::scratch_dir("io_disk_full");
  const auto scene = test::write_scene(dir, test::tiny_dam_break());
  fs::create_directories(dir / "mnt");
  // 200 KiB: the run starts, then a frame or checkpoint runs out of space; the tree is copied out
  const auto r = test::run_command(
      "unshare -rm sh -c \"mount -t tmpfs -o size=200k tmpfs " + q(dir / "mnt") + " && " + exe() + " run " + q(scene) +
      " -o " + q(dir / "mnt" / "run") + " --quiet --set checkpoint.every_steps=20; echo exit=\\$?; cp -r " +
      q(dir / "mnt" / "run") + " " + q(dir / "copy") + "\"");
  EXPECT_NE(r.output.find("exit=4"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("I/O error"), std::string::npos) << r.output;
  ASSERT_TRUE(fs::exists(dir / "copy"));
  for (const auto& e : fs::recursive_directory_iterator(dir / "copy")) {
    EXPECT_EQ(e.path().extension(), e.path().extension() == ".tmp" ? ".none" : e.path().extension())
        << "partial file left: " << e.path();
    if (e.path().extension() == ".h5") EXPECT_NO_THROW(io::read_checkpoint(e.path())) << e.path();
  }
  expect_valid_pvd(dir / "copy" / "tiny.pvd");
  const std::string pvd = test::read_text(dir / "copy" / "tiny.pvd");
  for (const auto& e : fs::directory_iterator(dir / "copy" / "frames")) {
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(e.path().c_str());
    reader->Update();
    EXPECT_GT(reader->GetOutput()->GetNumberOfPoints(), 0) << e.path() << " is incomplete";
  }
}

// ----------------------------------------------------------------------------------- frames (VTK)

TEST(Frames, PrecisionAndFieldsAreWhatTheSceneAsksFor) {
  const auto dir = test::scratch_dir("frames_precision");
  const auto scene = test::write_scene(dir, test::tiny_dam_break());
  for (const std::string prec : {"float32", "float64"}) {
    const auto run = dir / prec;
    const auto r = test::run_command(exe() + " run " + q(scene) + " -o " + q(run) +
                                     " --quiet --set time.end=0.004 --set output.precision=" + prec +
                                     " --set 'output.fields=[\"velocity\",\"density\",\"id\",\"kind\",\"body\"]'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    expect_valid_pvd(run / "tiny.pvd");
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName((run / "frames" / "tiny_000001.vtu").c_str());
    reader->Update();
    vtkUnstructuredGrid* g = reader->GetOutput();
    ASSERT_GT(g->GetNumberOfPoints(), 100);
    const int want = prec == "float64" ? VTK_DOUBLE : VTK_FLOAT;
    EXPECT_EQ(g->GetPoints()->GetDataType(), want);
    vtkPointData* pd = g->GetPointData();
    ASSERT_NE(pd->GetArray("velocity"), nullptr);
    EXPECT_EQ(pd->GetArray("velocity")->GetDataType(), want);
    EXPECT_EQ(pd->GetArray("velocity")->GetNumberOfComponents(), 3);
    EXPECT_EQ(pd->GetArray("density")->GetDataType(), want);
    EXPECT_EQ(pd->GetArray("id")->GetDataTypeSize(), 8);
    EXPECT_NE(pd->GetArray("body"), nullptr);
    EXPECT_EQ(pd->GetArray("pressure"), nullptr) << "not asked for";
    EXPECT_EQ(pd->GetArray("normal"), nullptr) << "not asked for";
  }
}
