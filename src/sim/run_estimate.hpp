#pragma once
// What a run will cost before it starts (issue 35, point 4): particles per body, memory, steps, wall time on
// this machine (from a short calibration) and disk for frames and checkpoints, with warnings past limits the
// user sets. `varsph info` prints it.
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace varsph {

struct EstimateLimits {
  double memory_gb = 0;   // warn above; 0 = 80 % of this machine's memory
  double disk_gb = 0;     // warn above; 0 = the free space of the working directory's file system
  double hours = 24;      // warn above
  double calibrate_max_particles = 1e5;  // above: calibrate on a coarser copy of the scene and scale
};

struct RunEstimate {
  std::vector<double> body_particles;  // per scene body
  double fluid = 0, boundary = 0;
  bool scaled = false;                 // from a coarser copy (spacing x `coarsening`)
  double coarsening = 1;
  double memory_bytes = 0;             // measured bytes per particle x particles
  double steps = 0;                    // time.end / dt (dt after the calibration steps)
  double seconds_per_step = 0;         // measured on this machine, with this build's default threads
  int threads = 1;
  int calibration_steps = 0;
  double frames = 0, bytes_per_frame = 0, bytes_static = 0, bytes_frames = 0, bytes_checkpoint = 0;
  double static_share = 0;             // static walls / all particles (what lean frames would leave out)
};

// Builds the scene (or a coarser copy of it when it would exceed `calibrate_max_particles`), runs a few
// steps, and estimates the full run. Throws what parsing or building the scene throws.
RunEstimate estimate_run(const scene::Scene& s, const std::vector<std::string>& overrides,
                         const EstimateLimits& limits);

template <int D>
class Simulation;

// One line for the start of `varsph run`: the disk its frames and checkpoints will take (no calibration:
// the particles of `sim`, the scene's output settings).
template <int D>
std::string disk_estimate_line(const scene::Scene& s, const Simulation<D>& sim);

// The lines `varsph info` prints, and the warnings of the limits (appended to `warnings`).
std::string describe_estimate(const scene::Scene& s, const RunEstimate& e, const EstimateLimits& limits,
                              std::vector<std::string>& warnings);

}  // namespace varsph
