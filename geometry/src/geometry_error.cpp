#include "varsph/geometry/geometry_error.h"

namespace varsph::geometry {

GeometryError::GeometryError(std::filesystem::path file, std::string problem)
    : std::runtime_error(file.empty() ? problem : file.string() + ": " + problem),
      file_(std::move(file)),
      problem_(std::move(problem)) {}

}  // namespace varsph::geometry
