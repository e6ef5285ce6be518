#pragma once
// An append-only CSV table (diagnostics.csv, probes.csv), flushed after every row so a crashed run
// keeps what it wrote. IoError names the file.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace varsph::io {

class CsvTable {
 public:
  CsvTable() = default;
  ~CsvTable();
  CsvTable(const CsvTable&) = delete;
  CsvTable& operator=(const CsvTable&) = delete;
  // Creates the file with a header; with `keep_rows_up_to_time`, an existing file is kept up to the
  // last row whose first-column-named `time` is <= that time (restart in the same directory).
  void open(const std::filesystem::path& path, const std::vector<std::string>& columns,
            double keep_rows_up_to_time = -1);
  bool is_open() const { return file_ != nullptr; }
  // Values are written with 17 significant digits; an empty string for a missing value.
  void row(const std::vector<std::string>& cells);
  static std::string num(double v);
  static std::string num(long v);

 private:
  std::FILE* file_ = nullptr;
  std::filesystem::path path_;
};

}  // namespace varsph::io
