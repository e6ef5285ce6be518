#include "io/csv_table.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/errors.hpp"

namespace varsph::io {

CsvTable::~CsvTable() {
  if (file_) std::fclose(file_);
}

void CsvTable::open(const std::filesystem::path& path, const std::vector<std::string>& columns,
                    double keep_rows_up_to_time) {
  path_ = path;
  std::string header;
  for (const auto& c : columns) header += (header.empty() ? "" : ",") + c;
  std::vector<std::string> kept;
  if (keep_rows_up_to_time >= 0) {
    std::ifstream in(path);
    std::string line;
    std::size_t time_col = 0;
    bool first = true;
    while (std::getline(in, line)) {
      std::vector<std::string> cells;
      std::stringstream ss(line);
      std::string c;
      while (std::getline(ss, c, ',')) cells.push_back(c);
      if (first) {
        for (std::size_t k = 0; k < cells.size(); ++k)
          if (cells[k] == "time") time_col = k;
        first = false;
        continue;
      }
      if (time_col < cells.size() && std::stod(cells[time_col]) <= keep_rows_up_to_time + 1e-12) kept.push_back(line);
    }
  }
  file_ = std::fopen(path.c_str(), "w");
  if (!file_) throw IoError(path.string() + ": cannot open for writing: " + std::strerror(errno));
  std::fprintf(file_, "%s\n", header.c_str());
  for (const auto& l : kept) std::fprintf(file_, "%s\n", l.c_str());
  if (std::fflush(file_) != 0) throw IoError(path.string() + ": write failed: " + std::strerror(errno));
}

void CsvTable::row(const std::vector<std::string>& cells) {
  std::string line;
  for (std::size_t k = 0; k < cells.size(); ++k) line += (k ? "," : "") + cells[k];
  if (std::fprintf(file_, "%s\n", line.c_str()) < 0 || std::fflush(file_) != 0)
    throw IoError(path_.string() + ": write failed (disk full?): " + std::strerror(errno));
}

std::string CsvTable::num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
std::string CsvTable::num(long v) { return std::to_string(v); }

}  // namespace varsph::io
