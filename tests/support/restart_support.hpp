#pragma once
// A checkpoint restart against an uninterrupted run, as the restart tests of bodies and waves run it.
#include <algorithm>
#include <filesystem>
#include <string>

#include "test_support.hpp"

namespace varsph::test {

// A checkpoint restart against an uninterrupted run: `scene` run to its end in dir/full, then the same scene
// stopped at `stop_time` in dir/part (it must write a checkpoint there) and continued from its last checkpoint
// into dir/part. Returns the table `table` (e.g. "bodies.csv") of both
// runs, or `error` with the failing command's output.
struct RestartedTables {
  std::string full, continued, error;
};
inline RestartedTables run_full_and_restarted(const std::filesystem::path& scene, const std::filesystem::path& dir,
                                              const std::string& stop_time, const std::string& table) {
  namespace fs = std::filesystem;
  const std::string run = varsph_exe().string() + " run " + scene.string() + " --quiet -o ";
  RestartedTables t;
  auto r = run_command(run + (dir / "full").string());
  if (r.exit_code != 0) return {{}, {}, "full run: " + r.output};
  t.full = read_text(dir / "full" / table);
  r = run_command(run + (dir / "part").string() + " --set time.end=" + stop_time);
  if (r.exit_code != 0) return {{}, {}, "run to " + stop_time + ": " + r.output};
  fs::path ckpt;  // the last one: names carry the zero-padded step
  for (const auto& e : fs::directory_iterator(dir / "part" / "checkpoints")) ckpt = std::max(ckpt, e.path());
  r = run_command(run + (dir / "part").string() + " --restart " + ckpt.string());
  if (r.exit_code != 0) return {{}, {}, "restart from " + ckpt.string() + ": " + r.output};
  t.continued = read_text(dir / "part" / table);
  return t;
}

}  // namespace varsph::test
