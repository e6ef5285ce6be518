#pragma once
// Time series of a run (probes.csv, diagnostics.csv) and what the study measures on them: the peak and its
// time, means over windows, norms of differences on a common time base (docs/study.md).
#include <filesystem>
#include <string>
#include <vector>

namespace varsph::study {

// A CSV table with a header; every cell parsed as a number (empty or unparsable: NaN).
struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> data;  // one vector per column
  const std::vector<double>* column(const std::string& name) const;
  std::size_t rows() const { return data.empty() ? 0 : data[0].size(); }
};
// Reads PATH; a missing file gives an empty table, a malformed one an InputError naming the file and line.
Table read_table(const std::filesystem::path& path);

struct Series {
  std::vector<double> t, v;  // increasing times, values (NaN samples dropped)
  bool empty() const { return t.empty(); }
};
// The column `name` of `table` against its `time` column (empty when either is missing).
Series series_of(const Table& table, const std::string& name);

enum class Norm { L1, L2, Linf };
Norm parse_norm(const std::string& s);  // "l1" | "l2" | "linf" (InputError otherwise)
const char* to_string(Norm n);

// Linear interpolation inside [t.front(), t.back()]; NaN outside.
double interpolate(const Series& s, double t);
std::vector<double> resample(const Series& s, const std::vector<double>& grid);

// Common time base of several levels on [t0, t1]: uniform, spacing the largest median sample interval of
// the series (no level is interpolated finer than the coarsest sampling), limited to where every series has
// samples. Empty if the window does not overlap every series.
std::vector<double> common_grid(const std::vector<const Series*>& levels, double t0, double t1);

struct Peak {
  double value = 0.0 / 0.0, time = 0.0 / 0.0;
  bool at_edge = false;      // the largest |value| is the first or last sample of the window (no true peak)
  double sampling = 0.0 / 0.0;  // median sample interval (the resolution of the peak time)
};
// Sample of largest magnitude in [t0, t1]; its time refined by the parabola through it and its neighbours.
Peak peak_of(const Series& s, double t0, double t1);

// Time average over [t0, t1] (trapezoidal, end points interpolated); NaN without overlap.
double window_mean(const Series& s, double t0, double t1);

// Norm of a - b over a uniform grid: L1 mean|a-b|, L2 sqrt(mean (a-b)^2) (RMS), Linf max|a-b|.
double norm_of_difference(const std::vector<double>& a, const std::vector<double>& b, Norm n);
double norm_of(const std::vector<double>& a, Norm n);

}  // namespace varsph::study
