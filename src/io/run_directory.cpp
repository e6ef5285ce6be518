#include "io/run_directory.hpp"

#include <cstdio>
#include <fstream>

#include "core/errors.hpp"

namespace varsph::io {

std::string RunDirectory::frame_relative(long index) const {
  char buf[32];
  std::snprintf(buf, sizeof buf, pieces ? "_%06ld.pvtu" : "_%06ld.vtu", index);
  return "frames/" + name + buf;
}
std::string RunDirectory::piece_relative(long index, int rank) const {
  char stem[32], file[48];
  std::snprintf(stem, sizeof stem, "_%06ld", index);
  std::snprintf(file, sizeof file, "_%06ld_%d.vtu", index, rank);
  return "frames/" + name + stem + "/" + name + file;
}
void RunDirectory::remove_frame(long index) const {
  std::error_code ec;
  std::filesystem::remove(frame(index), ec);
  char stem[32];
  std::snprintf(stem, sizeof stem, "_%06ld", index);
  std::filesystem::remove_all(frames() / (name + stem), ec);
}
std::filesystem::path RunDirectory::frame(long index) const { return root / frame_relative(index); }

RunDirectory prepare_run_directory(const std::filesystem::path& root, const std::string& name, bool overwrite,
                                   bool keep_existing) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(root, ec) && !fs::is_directory(root, ec))
    throw InputError(root.string() + ": exists and is not a directory");
  if (fs::exists(root, ec) && !fs::is_empty(root, ec) && !keep_existing) {
    if (!overwrite)
      throw InputError(root.string() + ": output directory exists and is not empty (use --overwrite to replace "
                                       "it, or -o to choose another)");
    for (const auto& entry : fs::directory_iterator(root)) fs::remove_all(entry.path(), ec);
  }
  RunDirectory dir{root, name};
  for (const fs::path& p : {dir.root, dir.frames(), dir.checkpoints(), dir.post()}) {
    fs::create_directories(p, ec);
    if (ec) throw IoError(p.string() + ": cannot create directory: " + ec.message());
  }
  // probe writability now rather than after the first hour of simulation
  const fs::path probe = root / ".write_test";
  {
    std::ofstream out(probe);
    if (!out || !(out << "x") || !out.flush())
      throw IoError(root.string() + ": output directory is not writable");
  }
  fs::remove(probe, ec);
  return dir;
}

}  // namespace varsph::io
