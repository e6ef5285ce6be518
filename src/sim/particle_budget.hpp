#pragma once
// Particle counts estimated before anything is sampled, against particles.max_count (docs/scene.md):
// a scene whose bodies would produce more is refused (InputError, exit 2) naming the body and the numbers,
// instead of running out of memory minutes later.
#include <string>

#include "scene/scene.hpp"

namespace varsph {

// particles.max_count of the scene (default 1e7)
double max_particles(const scene::Scene& s);

// Particles body `index` will produce (box, tank, sphere, points: from its size and dx; mesh bodies: 0,
// the geometry module estimates them from the mesh before sampling).
double estimate_body_particles(const scene::Scene& s, std::size_t index);

// Throws InputError when the non-mesh bodies' estimates add up to more than max_particles(s).
void check_particle_budget(const scene::Scene& s);

// Throws InputError when `count` particles (built so far, after body `index`) exceed max_particles(s).
void check_particle_count(const scene::Scene& s, std::size_t index, double count);

}  // namespace varsph
