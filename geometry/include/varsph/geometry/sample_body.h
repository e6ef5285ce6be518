#pragma once
#include "varsph/geometry/body.h"

namespace varsph::geometry {

// Reads, repairs, transforms and samples one body.
// Inputs:
//   request  see BodyRequest (spacing > 0, dimension 2|3, fill "surface"|"volume", layers >= 1,
//            layer_side "inside"|"outside")
// Returns the particles (see SampledBody).
// Throws GeometryError naming the file and the problem (missing/unreadable/empty/unsupported file,
// not closed or self-intersecting mesh for a volume fill, invalid request fields).
SampledBody sample_body(const BodyRequest& request);

}  // namespace varsph::geometry
