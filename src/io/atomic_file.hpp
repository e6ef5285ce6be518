#pragma once
// Files that readers may open at any moment are written to a temporary name and renamed into place,
// so a running or crashed run never leaves a half-written .pvd, frame or checkpoint behind.
#include <filesystem>
#include <functional>
#include <string>

namespace varsph::io {

// Calls write(tmp_path) then renames tmp_path to `path`. IoError (exit 4) names the file and the cause.
void write_atomically(const std::filesystem::path& path, const std::function<void(const std::filesystem::path&)>& write);
// Writes a whole text file atomically.
void write_text_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace varsph::io
