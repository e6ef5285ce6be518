#pragma once
// Deviation between two runs, seed paper eq. (70): D(t) = max_i |q_i^A(t) - q_i^B(t)| over fluid
// particles matched by `id`, at the frames whose times agree within 1e-9 s (CONTRACT.md, `varsph compare`).
#include <filesystem>
#include <string>
#include <vector>

namespace varsph::io {

struct DeviationRow {
  double time = 0, d_max = 0, d_mean = 0, d_rms = 0;
  long matched = 0;          // fluid particles in both frames (the deviation is over these)
  long only_a = 0, only_b = 0;  // fluid particles in one frame only (removed by the other run's health rules)
};

struct CompareOptions {
  std::filesystem::path run_a, run_b;  // run directories (one .pvd inside) or .pvd files
  std::filesystem::path output;        // DIR: deviation.csv, deviation.pvd, frames/
  bool overwrite = false;
  double time_tolerance = 1e-9;        // [s]
};

// Writes DIR/deviation.csv (time,D_max,D_mean,D_rms,matched,only_a,only_b) and DIR/deviation.pvd with
// frames carrying `deviation` (x_A - x_B, 3 components) and `deviation_magnitude` at run A's fluid
// positions of the particles both frames hold. Particles one run removed (health.*) are left out and
// counted per frame. InputError (exit 2) when the runs cannot be matched: no common times, or other
// fluid particle sets at the first common time.
std::vector<DeviationRow> compare_runs(const CompareOptions& o);

}  // namespace varsph::io
