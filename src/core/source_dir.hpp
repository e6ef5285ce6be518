#pragma once
// Where the tests and benchmarks find pipelines/ (their scenes): $VARSPH_SOURCE_DIR when it is set and not
// empty, else the source tree they were configured from. A program that travels without its source tree
// (scripts/device_bundle.sh: the bundle carries the scenes, scripts/device_check.sh points here) reads
// the scenes where it runs, not at a path of the machine that built it.
#include <cstdlib>
#include <string>

namespace varsph {

inline std::string source_dir_or(const char* configured) {
  const char* env = std::getenv("VARSPH_SOURCE_DIR");
  return env && *env ? std::string(env) : std::string(configured);
}

}  // namespace varsph
