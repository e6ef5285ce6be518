#pragma once
// Helpers shared by the test suites: scene paths, small scenes built in code, running the binary.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/source_dir.hpp"

namespace varsph::test {

// $VARSPH_SOURCE_DIR overrides the configured tree (a bundled test binary run elsewhere, scripts/device_check.sh)
inline std::filesystem::path source_dir() { return source_dir_or(VARSPH_SOURCE_DIR); }
inline std::filesystem::path binary_dir() { return VARSPH_BINARY_DIR; }
inline std::filesystem::path varsph_exe() { return binary_dir() / "bin" / "varsph"; }

// A fresh scratch directory under the build tree, unique per test name.
inline std::filesystem::path scratch_dir(const std::string& name) {
  const auto d = binary_dir() / "test_scratch" / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct CommandResult {
  int exit_code;
  std::string output;  // stdout and stderr together
};

// Runs a shell command, capturing its output and exit code.
inline CommandResult run_command(const std::string& cmd) {
  const auto out = std::filesystem::temp_directory_path() /
                   ("varsph_cmd_" + std::to_string(std::hash<std::string>{}(cmd)) + ".txt");
  const int status = std::system((cmd + " > " + out.string() + " 2>&1").c_str());
  CommandResult r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(out)};
  std::filesystem::remove(out);
  return r;
}

}  // namespace varsph::test
