#include <cstdio>

#include "app/commands.hpp"
#include "io/run_directory.hpp"
#include "scene/sanity.hpp"
#include "scene/scene.hpp"
#include "sim/sample_report.hpp"

namespace varsph {

int command_sample(const CommandArgs& a) {
  const scene::Scene s = scene::parse_scene(a.scene, a.overrides);
  for (const auto& w : scene::check_sanity(s)) std::fprintf(stderr, "varsph: warning: %s: %s\n", s.file.string().c_str(), w.c_str());
  const auto dir = io::prepare_run_directory(a.output, s.name, a.overwrite, false);
  std::fputs(write_sampled_particles(s, dir.root).c_str(), stdout);
  return 0;
}

}  // namespace varsph
