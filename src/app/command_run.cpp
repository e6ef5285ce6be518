#include "app/commands.hpp"
#include "scene/scene.hpp"
#include "sim/runner.hpp"

namespace varsph {

int command_run(const CommandArgs& a) {
  const scene::Scene s = scene::parse_scene(a.scene, a.overrides);
  RunOptions o;
  o.output_dir = a.output.empty() ? std::filesystem::path("runs") / s.name : std::filesystem::path(a.output);
  o.overwrite = a.overwrite;
  o.quiet = a.quiet;
  o.threads = a.threads;
  o.restart = a.restart;
  o.command_line = a.argv;
  install_signal_handlers();
  return run_scene(s, o);
}

}  // namespace varsph
