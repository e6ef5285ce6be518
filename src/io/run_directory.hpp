#pragma once
// The run directory of CONTRACT.md: NAME.pvd, frames/, diagnostics.csv, probes.csv, removed.csv,
// checkpoints/, run.json, post/.
#include <filesystem>
#include <string>

namespace varsph::io {

struct RunDirectory {
  std::filesystem::path root;
  std::string name;
  std::filesystem::path pvd() const { return root / (name + ".pvd"); }
  std::filesystem::path frames() const { return root / "frames"; }
  std::filesystem::path frame(long index) const;          // frames/NAME_000042.vtu
  std::string frame_relative(long index) const;           // "frames/NAME_000042.vtu"
  std::filesystem::path diagnostics() const { return root / "diagnostics.csv"; }
  std::filesystem::path probes() const { return root / "probes.csv"; }
  std::filesystem::path removed() const { return root / "removed.csv"; }  // particles removed by health.*
  std::filesystem::path checkpoints() const { return root / "checkpoints"; }
  std::filesystem::path run_json() const { return root / "run.json"; }
  std::filesystem::path post() const { return root / "post"; }
};

// Creates the directory tree. An existing non-empty directory is refused (InputError, exit 2) unless
// `reuse` (--overwrite clears it first; --restart keeps it). Unwritable: IoError (exit 4).
RunDirectory prepare_run_directory(const std::filesystem::path& root, const std::string& name, bool overwrite,
                                   bool keep_existing);

}  // namespace varsph::io
