// Replays fuzz/regressions/<target>/ (crashers and hangs the fuzzing campaigns found, and the findings of
// issue 16) through the harnesses' own functions (fuzz/fuzz_targets.hpp) in the normal build. A file named
// refused_* must be refused with the documented error (exit 2 in the solver), accepted_* must be read;
// a crash, a hang (CTest timeout) or another exception fails.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "fuzz_targets.hpp"

namespace fs = std::filesystem;

namespace {

int replay(const std::string& target, bool (*run)(const std::string&, const std::uint8_t*, std::size_t),
           const std::string& ext) {
  const fs::path dir = fs::path(VARSPH_SOURCE_DIR) / "fuzz" / "regressions" / target;
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    std::ifstream in(e.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const bool accepted = run(ext, reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    if (name.rfind("refused_", 0) == 0) EXPECT_FALSE(accepted) << e.path();
    else if (name.rfind("accepted_", 0) == 0) EXPECT_TRUE(accepted) << e.path();
    else ADD_FAILURE() << e.path() << ": name it refused_* or accepted_*";
    ++n;
  }
  return n;
}

bool scene(const std::string&, const std::uint8_t* d, std::size_t n) { return varsph::fuzz::run_scene(d, n); }
bool mesh(const std::string& ext, const std::uint8_t* d, std::size_t n) { return varsph::fuzz::run_mesh(ext, d, n); }
bool checkpoint(const std::string&, const std::uint8_t* d, std::size_t n) { return varsph::fuzz::run_checkpoint(d, n); }

}  // namespace

TEST(FuzzRegressions, Scene) { EXPECT_GT(replay("scene", scene, ".json"), 0); }
TEST(FuzzRegressions, Stl) { EXPECT_GT(replay("stl", mesh, ".stl"), 0); }
TEST(FuzzRegressions, Obj) { EXPECT_GT(replay("obj", mesh, ".obj"), 0); }
TEST(FuzzRegressions, Off) { EXPECT_GT(replay("off", mesh, ".off"), 0); }
TEST(FuzzRegressions, Ply) { EXPECT_GT(replay("ply", mesh, ".ply"), 0); }
TEST(FuzzRegressions, Poly2d) { EXPECT_GT(replay("poly2d", mesh, ".poly2d"), 0); }
TEST(FuzzRegressions, Checkpoint) { replay("checkpoint", checkpoint, ".h5"); }
