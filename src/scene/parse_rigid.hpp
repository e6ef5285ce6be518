#pragma once
// Scene keys of rigid bodies (kind "rigid"), their moorings and contact (docs/scene.md "Rigid bodies").
#include <string>

#include "scene/json_reader.hpp"
#include "scene/scene.hpp"

namespace varsph::scene {

// bodies.N.* of a rigid body: mass properties, initial angular velocity, constraints, layers, cylinder axis.
void parse_rigid_body(JsonReader& r, const std::string& base, int dim, BodySpec& b);
// Top-level `moorings` and `contact` (after the bodies: a mooring names rigid bodies by index).
void parse_moorings_and_contact(JsonReader& r, Scene& s);

}  // namespace varsph::scene
