#pragma once
// Error thrown by every function of the geometry module on invalid input (the solver maps it to
// exit code 2). what() reads "<file>: <problem>; <what was expected>".
#include <filesystem>
#include <stdexcept>
#include <string>

namespace varsph::geometry {

class GeometryError : public std::runtime_error {
 public:
  // file     the input file the problem is in (may be empty for in-memory input)
  // problem  what is wrong and what was expected
  GeometryError(std::filesystem::path file, std::string problem);
  const std::filesystem::path& file() const noexcept { return file_; }
  const std::string& problem() const noexcept { return problem_; }

 private:
  std::filesystem::path file_;
  std::string problem_;
};

}  // namespace varsph::geometry
