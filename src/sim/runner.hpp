#pragma once
// Drives a simulation to time.end: frames (VTU + PVD), diagnostics rows, progress, health checks,
// signals and run.json. Returns the process exit code of CONTRACT.md.
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace varsph {

namespace parallel {
class Communicator;
}

struct RunOptions {
  std::filesystem::path output_dir;
  bool overwrite = false;
  bool quiet = false;
  int threads = 0;  // 0 = OpenMP default
  std::filesystem::path restart;  // checkpoint to continue from (empty: fresh run)
  std::vector<std::string> command_line;
  // the ranks of a distributed run (mpirun; parallel/session.hpp); null: one process
  std::shared_ptr<parallel::Communicator> comm;
};

// Runs the scene; exceptions of the input kind propagate (exit 2), everything else is handled here.
int run_scene(const scene::Scene& scene, const RunOptions& options);

// Set by SIGINT / SIGTERM handlers; the run finishes its step, writes and exits 130 / 143.
void install_signal_handlers();
int pending_signal();

}  // namespace varsph
