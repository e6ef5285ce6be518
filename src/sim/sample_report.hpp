#pragma once
// `varsph sample`: the particles a scene's bodies produce, written as VTU with statistics.
#include <filesystem>
#include <string>

#include "scene/scene.hpp"

namespace varsph {

// Writes DIR/NAME_particles.vtu (arrays kind, normal, id, mass, density, body) and returns a report: counts
// by kind, count and box of particle centres per body (to check a mesh's transform), nearest-neighbour spacing
// statistics (min / mean / max, relative to dx).
std::string write_sampled_particles(const scene::Scene& s, const std::filesystem::path& dir);

}  // namespace varsph
