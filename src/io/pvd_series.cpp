#include "io/pvd_series.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

#include "io/atomic_file.hpp"

namespace varsph::io {

namespace {
// Shortest decimal that reads back to exactly `v` (std::to_chars without a precision).
std::string shortest(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}
}  // namespace

double frame_time_label(double t, double every) {
  if (!(every > 0) || !std::isfinite(t)) return t;
  const double k = std::nearbyint(t / every);
  if (std::abs(t - k * every) > std::min(kFrameTimeDrift, 1e-3 * every)) return t;
  // k * every carries its own rounding error (15 * 0.02 = 0.30000000000000004): snap to 15 digits
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.15g", k * every);
  return std::strtod(buf, nullptr);
}

void PvdSeries::add(double time, const std::string& relative_file, const std::string& static_file) {
  truncate_after(time - 1e-12);
  entries_.push_back({time, relative_file, static_file});
  write();
}

void PvdSeries::truncate_after(double t) {
  while (!entries_.empty() && entries_.back().time > t) entries_.pop_back();
}

void PvdSeries::load() {
  entries_.clear();
  std::ifstream in(path_);
  if (!in) return;
  std::string line;
  const std::regex re(R"re(timestep="([^"]+)".*file="([^"]+)")re");
  while (std::getline(in, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, re)) continue;
    if (line.find("part=\"1\"") != std::string::npos && !entries_.empty()) entries_.back().static_file = m[2];
    else entries_.push_back({std::stod(m[1]), m[2], ""});
  }
}

void PvdSeries::write() const {
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
  for (const auto& e : entries_) {
    out << "    <DataSet timestep=\"" << shortest(e.time) << "\" group=\"\" part=\"0\" file=\"" << e.file << "\"/>\n";
    if (!e.static_file.empty())
      out << "    <DataSet timestep=\"" << shortest(e.time) << "\" group=\"\" part=\"1\" file=\"" << e.static_file
          << "\"/>\n";
  }
  out << "  </Collection>\n</VTKFile>\n";
  write_text_atomically(path_, out.str());
}

}  // namespace varsph::io
