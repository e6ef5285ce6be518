#include <cstdio>

#include "app/commands.hpp"
#include "scene/scene.hpp"
#include "sim/scene_summary.hpp"

namespace varsph {

int command_info(const CommandArgs& a) {
  const scene::Scene s = scene::parse_scene(a.scene, a.overrides);
  std::fputs(describe_scene(s).c_str(), stdout);
  return 0;
}

}  // namespace varsph
