#include <cstdio>

#include "app/commands.hpp"
#include "scene/sanity.hpp"
#include "scene/scene.hpp"
#include "sim/runner.hpp"

namespace varsph {

int command_run(const CommandArgs& a) {
  std::vector<std::string> overrides = a.overrides;
  if (!a.device.empty()) overrides.push_back("execution.device=\"" + a.device + "\"");  // validated with the scene
  const scene::Scene s = scene::parse_scene(a.scene, overrides);
  for (const auto& w : scene::check_sanity(s)) std::fprintf(stderr, "varsph: warning: %s: %s\n", s.file.string().c_str(), w.c_str());
  RunOptions o;
  if (!a.output.empty()) o.output_dir = a.output;
  else if (!a.restart.empty())  // DIR/checkpoints/step_N.h5 -> DIR: continue in the run's own directory
    o.output_dir = std::filesystem::absolute(a.restart).parent_path().parent_path();
  else o.output_dir = std::filesystem::path("runs") / s.name;
  o.overwrite = a.overwrite;
  o.quiet = a.quiet;
  o.threads = a.threads;
  o.restart = a.restart;
  o.command_line = a.argv;
  install_signal_handlers();
  return run_scene(s, o);
}

}  // namespace varsph
