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
  // distributed runs: a frame is frames/NAME_000042.pvtu plus one piece per rank in
  // frames/NAME_000042/NAME_000042_R.vtu (the .pvd lists the .pvtu)
  bool pieces = false;
  std::filesystem::path frame(long index) const;          // frames/NAME_000042.vtu (or .pvtu)
  std::string frame_relative(long index) const;           // "frames/NAME_000042.vtu" (or .pvtu)
  std::string piece_relative(long index, int rank) const;  // "frames/NAME_000042/NAME_000042_3.vtu"
  void remove_frame(long index) const;                    // the frame and its pieces
  std::filesystem::path diagnostics() const { return root / "diagnostics.csv"; }
  std::filesystem::path probes() const { return root / "probes.csv"; }
  std::filesystem::path removed() const { return root / "removed.csv"; }  // particles removed by health.*
  std::filesystem::path bodies() const { return root / "bodies.csv"; }      // rigid bodies (kind "rigid")
  std::filesystem::path moorings() const { return root / "moorings.csv"; }  // their moorings
  std::filesystem::path checkpoints() const { return root / "checkpoints"; }
  std::filesystem::path run_json() const { return root / "run.json"; }
  std::filesystem::path post() const { return root / "post"; }
};

// Creates the directory tree. An existing non-empty directory is refused (InputError, exit 2) unless
// `reuse` (--overwrite clears it first; --restart keeps it). Unwritable: IoError (exit 4).
RunDirectory prepare_run_directory(const std::filesystem::path& root, const std::string& name, bool overwrite,
                                   bool keep_existing);

}  // namespace varsph::io
