#pragma once
// Scene keys of open boundaries: the top-level `open_boundaries` list (docs/scene.md "Open boundaries";
// the zones themselves are sim/open_boundaries.hpp).
#include "scene/json_reader.hpp"
#include "scene/scene.hpp"

namespace varsph::scene {

// Parses `open_boundaries` into s.open_boundaries (after domain and particles.spacing). Every check that
// needs no particles happens here (exit 2 naming the zone and the key): box on the lattice and inside the
// domain, direction along an axis and into the domain, inflow pointing into the domain, a profile file
// with finite values and strictly increasing times, zones that overlap one another.
void parse_open_boundaries(JsonReader& r, Scene& s);

}  // namespace varsph::scene
