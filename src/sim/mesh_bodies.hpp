#pragma once
// Mesh bodies are sampled by the CGAL geometry module (its own target); this is the solver-side seam.
#include <vector>

#include "core/real.hpp"
#include "scene/scene.hpp"

namespace varsph {

// Appends the particles (and outward normals for boundary bodies) of scene body `index`.
template <int D>
void sample_mesh_body(const scene::Scene& s, std::size_t index, std::vector<Vec<D>>& positions,
                      std::vector<Vec<D>>& normals);

}  // namespace varsph
