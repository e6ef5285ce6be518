#pragma once
#include <cstddef>
#include <cstdint>

#include "core/host_device.hpp"

namespace varsph::physics {

// Selects the boundary particles of some scene bodies (rigid bodies: the reaction pass runs over their
// particles only). Empty (body == nullptr): every boundary particle.
struct BoundaryFilter {
  const std::int32_t* body = nullptr;   // per particle: scene body index
  const std::uint8_t* on = nullptr;     // per scene body: 1 when selected
  std::int32_t count = 0;               // scene bodies
  VARSPH_HD bool selects(std::size_t i) const {
    if (!body) return true;
    const std::int32_t b = body[i];
    return b >= 0 && b < count && on[b] != 0;
  }
};

}  // namespace varsph::physics
