#pragma once
// Schema of the health.* keys (docs/scene.md "Health"; the rules themselves are sim/health.hpp).
#include "scene/json_reader.hpp"
#include "scene/scene.hpp"

namespace varsph::scene {

HealthSpec parse_health(JsonReader& r);

}  // namespace varsph::scene
