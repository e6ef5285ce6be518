#include <cstdio>

#include "app/commands.hpp"
#include "scene/sanity.hpp"
#include "scene/scene.hpp"
#include "sim/scene_summary.hpp"

namespace varsph {

int command_info(const CommandArgs& a) {
  const scene::Scene s = scene::parse_scene(a.scene, a.overrides);
  std::fputs(describe_scene(s).c_str(), stdout);
  // unusual but accepted values (scene/sanity.hpp; docs/scene.md "Sanity checks")
  const std::vector<std::string> warnings = scene::check_sanity(s);
  if (warnings.empty()) std::fputs("warnings           none\n", stdout);
  for (const auto& w : warnings) std::printf("warning            %s\n", w.c_str());
  return 0;
}

}  // namespace varsph
