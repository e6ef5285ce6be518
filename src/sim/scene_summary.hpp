#pragma once
// What `varsph info` prints: the resolved parameters of a scene, built without running it.
#include <string>

#include "scene/scene.hpp"

namespace varsph {

// Builds the simulation (particles, grid) and describes it: counts by kind, dx, h, support radius,
// c0, B, mean neighbours, dt, the CFL limits and the variational dt bound estimate.
std::string describe_scene(const scene::Scene& s);

// The `setup` line of `varsph info`: the set-up (issue 35) and the keys it filled in.
std::string setup_line(const scene::Scene& s);

}  // namespace varsph
