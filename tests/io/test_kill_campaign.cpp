// kill -9 at random moments of a run (issue 16; validation tier): after each of 20 kills the .pvd is
// complete XML that names only frames VTK reads, every frame in frames/ reads, and the run restarted
// from its newest checkpoint (or from scratch when the kill came before the first one) ends in the
// same state, bitwise, as an uninterrupted run.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <chrono>
#include <cstdio>
#include <random>
#include <thread>

#include "io/checkpoint.hpp"
#include "results_scenes.hpp"
#include "test_support.hpp"

extern char** environ;

using namespace varsph;
namespace fs = std::filesystem;

namespace {

std::string exe() { return test::varsph_exe().string(); }

pid_t spawn(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> a = {exe()};
  a.insert(a.end(), args.begin(), args.end());
  std::vector<char*> argv;
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

// The newest checkpoint of a run directory (empty path if none).
fs::path newest_checkpoint(const fs::path& run) {
  const auto kept = io::list_checkpoints(run / "checkpoints");
  return kept.empty() ? fs::path() : kept.back().second;
}

// A frame VTK reads, with the solver's field data; returns its number of points (-1 if unreadable).
long read_frame(const fs::path& vtu) {
  vtkNew<vtkXMLUnstructuredGridReader> r;
  r->SetFileName(vtu.c_str());
  r->Update();
  if (r->GetErrorCode() != 0 || !r->GetOutput() || !r->GetOutput()->GetFieldData()->GetArray("step")) return -1;
  return long(r->GetOutput()->GetNumberOfPoints());
}

// The .pvd parses as XML and every DataSet it names is a frame VTK reads; returns the number of entries.
int check_pvd(const fs::path& pvd, long points) {
  vtkNew<vtkXMLDataParser> p;
  p->SetFileName(pvd.c_str());
  EXPECT_EQ(p->Parse(), 1) << pvd << " is not complete XML";
  vtkXMLDataElement* root = p->GetRootElement();
  if (!root) return -1;
  vtkXMLDataElement* coll = root->FindNestedElementWithName("Collection");
  EXPECT_NE(coll, nullptr);
  if (!coll) return -1;
  int n = 0;
  for (int k = 0; k < coll->GetNumberOfNestedElements(); ++k) {
    const char* f = coll->GetNestedElement(k)->GetAttribute("file");
    EXPECT_NE(f, nullptr);
    if (!f) continue;
    EXPECT_EQ(read_frame(pvd.parent_path() / f), points) << f;
    ++n;
  }
  return n;
}

bool same_state(const io::Checkpoint& a, const io::Checkpoint& b) {
  if (a.header.step != b.header.step || a.header.time != b.header.time || a.arrays.size() != b.arrays.size())
    return false;
  for (std::size_t k = 0; k < a.arrays.size(); ++k)
    if (a.arrays[k].name != b.arrays[k].name || a.arrays[k].bytes != b.arrays[k].bytes) return false;
  return a.header.integrator_state == b.header.integrator_state;
}

}  // namespace

TEST(KillCampaign, TwentyKillsLeaveReadableOutputAndABitwiseRestart) {
  const auto dir = test::scratch_dir("kill_campaign");
  auto j = test::tiny_dam_break();
  j["time"]["end"] = 0.2;  // 1000 steps, 50 frames, a checkpoint every 40 steps
  j["output"]["every"] = 0.004;
  j["checkpoint"] = {{"every_steps", 40}};
  const auto scene = test::write_scene(dir, j);
  const std::vector<std::string> common = {"--threads", "1", "--quiet"};

  auto run_to_end = [&](std::vector<std::string> args, const fs::path& log) {
    args.insert(args.end(), common.begin(), common.end());
    const pid_t pid = spawn(args, log);
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(run_to_end({"run", scene.string(), "-o", (dir / "straight").string()}, dir / "straight.log"), 0)
      << test::read_text(dir / "straight.log");
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const io::Checkpoint reference = io::read_checkpoint(newest_checkpoint(dir / "straight"));
  const long points = long(reference.header.particles);

  std::mt19937 rng(16);
  std::uniform_real_distribution<double> when(0.02, 1.0);
  int killed = 0, with_checkpoint = 0, frames_checked = 0;
  for (int k = 0; k < 20; ++k) {
    const auto run = dir / ("run" + std::to_string(k));
    std::vector<std::string> args = {"run", scene.string(), "-o", run.string()};
    args.insert(args.end(), common.begin(), common.end());
    const pid_t pid = spawn(args, dir / "kill.log");
    ASSERT_GT(pid, 0);
    std::this_thread::sleep_for(std::chrono::duration<double>(when(rng) * wall));
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    if (WIFSIGNALED(status)) ++killed;

    // what the killed run left is readable
    if (fs::exists(run / "tiny.pvd")) frames_checked += check_pvd(run / "tiny.pvd", points);
    if (fs::exists(run / "frames"))
      for (const auto& f : fs::directory_iterator(run / "frames"))
        if (f.path().extension() == ".vtu") EXPECT_EQ(read_frame(f.path()), points) << f.path();

    // and restarts to the straight run's final state
    const fs::path ckpt = newest_checkpoint(run);
    int rc;
    if (!ckpt.empty()) {
      ++with_checkpoint;
      rc = run_to_end({"run", scene.string(), "--restart", ckpt.string()}, dir / "restart.log");
    } else {
      rc = run_to_end({"run", scene.string(), "-o", run.string(), "--overwrite"}, dir / "restart.log");
    }
    ASSERT_EQ(rc, 0) << "try " << k << ": " << test::read_text(dir / "restart.log");
    const io::Checkpoint end = io::read_checkpoint(newest_checkpoint(run));
    EXPECT_TRUE(same_state(end, reference)) << "try " << k << " (restart from " << ckpt << ") ends elsewhere";
    EXPECT_EQ(check_pvd(run / "tiny.pvd", points), check_pvd(dir / "straight" / "tiny.pvd", points)) << "try " << k;
    fs::remove_all(run);
  }
  std::printf("[ kill -9  ] 20 tries over a %.2f s run: %d killed mid-run, %d restarted from a checkpoint, %d from "
              "scratch; %d .pvd entries read back; every restart bitwise equal to the straight run\n",
              wall, killed, with_checkpoint, 20 - with_checkpoint, frames_checked);
  EXPECT_GE(killed, 15);  // the moments are spread over the run: nearly all kills land mid-run
}
