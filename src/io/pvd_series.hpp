#pragma once
// The .pvd time series: rewritten atomically after every frame so it is valid XML at any moment.
#include <filesystem>
#include <string>
#include <vector>

namespace varsph::io {

// Frame times drift as dt is summed (the 0.3 s frame at 0.29999999999998328). The .pvd gets the time
// rounded to the nearest multiple of the output interval `every` when the frame lies within
// kFrameTimeDrift of it (the tolerance frames of two runs are matched with, CONTRACT.md), written as the
// shortest decimal that reads back to the same double; other frames (t_end, a failure, an adaptive dt)
// keep their exact time. The VTU field data `time` always holds the exact simulated time.
inline constexpr double kFrameTimeDrift = 1e-9;
double frame_time_label(double t, double every);

class PvdSeries {
 public:
  explicit PvdSeries(std::filesystem::path path) : path_(std::move(path)) {}
  // Adds (or, for a restart, replaces every entry at or after `time`) and rewrites the file. `static_file`
  // (issue 35, output.static_boundary = "once"): the static walls the frame leaves out, listed as part 1 of
  // the same time step, so that ParaView's own .pvd reader shows both.
  void add(double time, const std::string& relative_file, const std::string& static_file = "");
  // Drops entries with time > t (restart in the same directory), without writing.
  void truncate_after(double t);
  // Reads an existing series (restart); missing file = empty series.
  void load();
  void write() const;
  const std::filesystem::path& path() const { return path_; }
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    double time;
    std::string file;
    std::string static_file;  // part 1, or ""
  };
  std::filesystem::path path_;
  std::vector<Entry> entries_;
};

}  // namespace varsph::io
