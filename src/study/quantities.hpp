#pragma once
// Quantities of interest of a study and their convergence across the levels: for every probe column and the
// run's global series (energies, momentum, max speed) the peak value, the time of the peak, the mean and the
// end value over each window and the whole series in a norm, each with its observed order, Richardson
// estimate and per-level errors (docs/study.md).
#include <filesystem>
#include <string>
#include <vector>

#include "study/child_process.hpp"
#include "study/level_plan.hpp"
#include "study/richardson.hpp"
#include "study/time_series.hpp"

namespace varsph::study {

// One run of the study (a level or an ablation variant) and what it wrote.
struct LevelRun {
  LevelSpec spec;
  std::filesystem::path dir;  // its run directory
  ChildResult child;
  bool reused = false;        // an earlier study's completed run with the same resolved scene (--reuse)
  std::string status, message;  // run.json
  long steps = 0;
  double solver_wall = 0;     // run.json timings.wall_seconds (the time loop only)
  Table probes, diagnostics;
  bool ok() const { return child.exit_code == 0; }
  double particle_steps() const { return double(steps) * double(spec.fluid); }
};

// Reads run.json, probes.csv and diagnostics.csv of `r.dir` into `r`.
void load_run_outputs(LevelRun& r);

// The series every run is measured on: probe columns (in probes.csv order), then kinetic, potential and
// total energy, momentum components and the largest speed from diagnostics.csv.
std::vector<std::string> series_names(const std::vector<const LevelRun*>& runs);
Series run_series(const LevelRun& r, const std::string& name);

enum class Kind { Peak, PeakTime, Mean, End, Series };
const char* to_string(Kind k);

struct Quantity {
  std::string name;    // SERIES.peak, SERIES.t_peak, SERIES.mean[T0:T1], SERIES.end[T0:T1], SERIES.NORM[T0:T1]
  std::string series;
  Kind kind = Kind::Peak;
  Window window;
  std::vector<double> values;  // per level; for a series: the norm of the level's own series
  OrderEstimate est;
  double scale = 0;    // denominator of relative errors: |extrapolated| (or the finest value); series: its norm
  std::vector<double> grid;             // series: the common time base
  std::vector<std::vector<double>> resampled;  // series: each level on the grid
  std::vector<double> extrapolated_series;     // series: Richardson extrapolation on the grid (may be empty)
  double noise = 0;    // rounding floor: differences at or below it are no change (levels and ablations)
  bool rounding_only = false;  // the series lies within its vector's rounding floor at every level (zero by symmetry)
  double relative(double abs_error) const { return scale > 0 ? abs_error / scale : 0.0 / 0.0; }
};

struct AnalysisInput {
  std::vector<const LevelRun*> levels;  // coarsest first
  std::vector<double> refined;          // the refined parameter of each level (dx or dt)
  double formal_order = 2;
  std::vector<Window> windows;
  Norm norm = Norm::L2;
};
// Every quantity of every series and window; a series whose largest magnitude lies at the window's start or end
// in every level gets no peak and time of peak (no event: the end or start value is that quantity).
// The rounding floor of a component of a vector (Fx_wall and Fy_wall, momentum_x and momentum_y) is set by the
// largest component, not by its own size: a force that is zero by symmetry sums round-off of the others' size.
std::vector<Quantity> analyse(const AnalysisInput& in);

// Two series are components of one vector: names of equal length that differ in exactly one character, and
// that character is x, y or z in both (Fx_body1 / Fy_body1, momentum_x / momentum_z).
bool vector_components(const std::string& a, const std::string& b);

// The value of a scalar quantity on one run (peak, peak time, mean, end); for Kind::Series the norm of
// the run's series on its own samples in the window.
double quantity_value(const Series& s, Kind kind, const Window& w, Norm norm);
// Distance between two runs' series in the window on their common time base (Kind::Series), or the
// difference of their scalar values (other kinds).
double quantity_difference(const Series& a, const Series& b, Kind kind, const Window& w, Norm norm);

}  // namespace varsph::study
