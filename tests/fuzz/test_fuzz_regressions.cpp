// Replays fuzz/regressions/<target>/ (crashers and hangs the fuzzing campaigns found, and the findings of
// issue 16) through the harnesses' own functions (fuzz/fuzz_targets.hpp) in the normal build. A file named
// refused_* must be refused with the documented error (exit 2 in the solver), accepted_* must be read;
// a crash, a hang (CTest timeout) or another exception fails.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "fuzz_targets.hpp"

namespace fs = std::filesystem;

namespace {

// The harnesses' scratch files (fuzz_targets.hpp) go to a directory of this test process, removed at the
// end, so that test runs leave nothing in /dev/shm or /tmp.
class ScratchDir : public ::testing::Environment {
 public:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("varsph_fuzz_replay_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    ::setenv("VARSPH_FUZZ_TMP", dir_.c_str(), 1);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

 private:
  fs::path dir_;
};
[[maybe_unused]] ::testing::Environment* const kScratch = ::testing::AddGlobalTestEnvironment(new ScratchDir);

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

// The mesh readers alone (fuzz_<fmt>_read): every mesh regression, whether the reader accepts it or not
// (refused_* may be refused later, by the domain or the particle budget); a crash, a hang or an exception
// other than GeometryError fails.
TEST(FuzzRegressions, MeshReadersAlone) {
  for (const std::string fmt : {"stl", "obj", "off", "ply"}) {
    int n = 0;
    for (const auto& e : fs::directory_iterator(fs::path(VARSPH_SOURCE_DIR) / "fuzz" / "regressions" / fmt)) {
      std::ifstream in(e.path(), std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      EXPECT_NO_THROW(varsph::fuzz::run_mesh_read("." + fmt, reinterpret_cast<const std::uint8_t*>(bytes.data()),
                                                   bytes.size()))
          << e.path();
      ++n;
    }
    EXPECT_GT(n, 0) << fmt;
  }
}
