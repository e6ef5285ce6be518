#include "io/pvd_series.hpp"

#include <fstream>
#include <iomanip>
#include <regex>
#include <sstream>

#include "io/atomic_file.hpp"

namespace varsph::io {

void PvdSeries::add(double time, const std::string& relative_file) {
  truncate_after(time - 1e-12);
  entries_.push_back({time, relative_file});
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
    if (std::regex_search(line, m, re)) entries_.push_back({std::stod(m[1]), m[2]});
  }
}

void PvdSeries::write() const {
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
  out << std::setprecision(17);
  for (const auto& e : entries_)
    out << "    <DataSet timestep=\"" << e.time << "\" group=\"\" part=\"0\" file=\"" << e.file << "\"/>\n";
  out << "  </Collection>\n</VTKFile>\n";
  write_text_atomically(path_, out.str());
}

}  // namespace varsph::io
