#pragma once
// Lean frames (issue 35, output.static_boundary = "once"): which particles are static walls, written once in
// a file of their own, and which go into every frame (fluid, moving walls, bodies).
#include <cstdint>
#include <vector>

#include "scene/scene.hpp"

namespace varsph {

// Per scene body: true when its particles never move: a "boundary" body without `motion`. A body with a
// motion, or of any other kind (fluid, a fluid-driven "rigid" body), is written in every frame.
inline std::vector<bool> static_bodies(const scene::Scene& s) {
  std::vector<bool> out;
  for (const auto& b : s.bodies) out.push_back(b.kind == "boundary" && b.motion.is_null());
  return out;
}

// Splits the store's first `n` particles into the static walls and the rest (store indices, in store order).
template <class KindVec, class BodyVec>
void split_static(const KindVec& kind, const BodyVec& body, std::size_t n, const std::vector<bool>& is_static,
                  std::vector<std::uint32_t>& walls, std::vector<std::uint32_t>& rest) {
  walls.clear();
  rest.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const auto b = std::size_t(body[i]);
    const bool wall = kind[i] != 0 && b < is_static.size() && is_static[b];
    (wall ? walls : rest).push_back(std::uint32_t(i));
  }
}

}  // namespace varsph
