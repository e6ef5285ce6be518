#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <thread>

#include "app/commands.hpp"
#include "app/default_threads.hpp"
#include "parallel/collective.hpp"
#include "scene/sanity.hpp"
#include "scene/scene.hpp"
#include "sim/runner.hpp"

namespace varsph {

int command_run(const CommandArgs& a) {
  std::vector<std::string> overrides = a.overrides;
  if (!a.device.empty()) overrides.push_back("execution.device=\"" + a.device + "\"");  // validated with the scene
  // every rank parses the same scene; agreeing on errors keeps them from aborting one another
  std::optional<scene::Scene> parsed;
  parallel::collectively(*a.comm, [&] { parsed = scene::parse_scene(a.scene, overrides); });
  const scene::Scene& s = *parsed;
  if (a.comm->root())  // one warning per run, not one per rank
    for (const auto& w : scene::check_sanity(s)) std::fprintf(stderr, "varsph: warning: %s: %s\n", s.file.string().c_str(), w.c_str());
  RunOptions o;
  if (!a.output.empty()) o.output_dir = a.output;
  else if (!a.restart.empty())  // DIR/checkpoints/step_N.h5 -> DIR: continue in the run's own directory
    o.output_dir = std::filesystem::absolute(a.restart).parent_path().parent_path();
  else o.output_dir = std::filesystem::path("runs") / s.name;
  o.overwrite = a.overwrite;
  o.quiet = a.quiet;
  o.threads = a.threads;
  o.comm = a.comm;
  // ranks sharing a machine share its cores unless told otherwise (--threads, OMP_NUM_THREADS)
  if (o.threads == 0 && a.comm->size() > 1 && !std::getenv("OMP_NUM_THREADS"))
    o.threads = std::max(1, int(std::thread::hardware_concurrency()) / std::max(1, a.comm->node_size()));
  // one process: one thread per core the load average says is free (app/default_threads.hpp)
  if (o.threads == 0 && a.comm->size() == 1 && !std::getenv("OMP_NUM_THREADS")) {
    const int cores = std::max(1, int(std::thread::hardware_concurrency()));
    const double load = load_average();
    o.threads = threads_for_load(cores, load);
    if (o.threads < cores && !a.quiet)
      std::fprintf(stderr, "varsph: note: load average %.2g on %d cores: running on %d thread(s), one per free core "
                   "(--threads N or OMP_NUM_THREADS sets it; README \"Threads on a busy machine\")\n", load, cores,
                   o.threads);
  }
  o.restart = a.restart;
  o.command_line = a.argv;
  install_signal_handlers();
  return run_scene(s, o);
}

}  // namespace varsph
