#pragma once
// Mesh bodies are sampled by the CGAL geometry module (its own target); this is the solver-side seam.
#include <vector>

#include "bodies/mass_properties.hpp"
#include "core/real.hpp"
#include "scene/scene.hpp"

namespace varsph {

// Appends the particles (and, for boundary bodies, the normals into the fluid and, when asked, each
// particle's distance to the fluid-wall interface, (layer + 1/2) dx) of scene body `index`; a mesh
// estimated to produce more than `max_particles` is refused before sampling (InputError naming the number).
template <int D>
void sample_mesh_body(const scene::Scene& s, std::size_t index, double max_particles,
                      std::vector<Vec<D>>& positions, std::vector<Vec<D>>& normals,
                      std::vector<Real>* interface_distance = nullptr);

// Which of `points` lie inside the closed mesh of scene body `index` (3D; transformed as sampled): 1 inside.
// Empty when it cannot tell: 2D bodies (outlines) and open meshes. Clears the fluid from mesh obstacles.
template <int D>
std::vector<char> inside_mesh_body(const scene::Scene& s, std::size_t index, const std::vector<Vec<D>>& points);

// Volume, centre of mass and inertia of a closed mesh body at unit density (rigid bodies): exact over the
// transformed mesh by signed tetrahedra. InputError for an open or self-intersecting mesh, and for 2D.
template <int D>
bodies::MassProperties mesh_mass_properties(const scene::Scene& s, std::size_t index);

}  // namespace varsph
