#pragma once
// The levels of a study: which `--set` each level's run gets (particle spacing with h/dx fixed, time step
// or CFL number), how many particles each has (sampled without running), the scheme's formal order, and the
// cost of each level predicted from a measured one (docs/study.md).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "study/study_options.hpp"

namespace varsph::study {

struct LevelSpec {
  int index = 0;
  std::filesystem::path scene;          // the scene file this level runs
  std::vector<std::string> overrides;   // the user's --set, then the level's own (level_sets)
  std::vector<std::string> level_sets;  // what makes this level: spacing, h, dt or cfl
  std::string probe_set;                // "probes=[...]" when the study added probes (front, forces), else ""
  std::string name;                     // the scene's name
  int dimension = 2;
  double dx = 0, h = 0, c0 = 0, t_end = 0;
  std::optional<double> dt, cfl;  // fixed step or CFL number of this level
  double dt_estimate = 0;         // fixed dt, or cfl h / c0 (the acoustic limit; the run may step shorter)
  double refined = 0;             // the refined parameter of the orders: dx (dx, both) or dt (dt)
  std::size_t fluid = 0, boundary = 0;
  double fluid_mass = 0;          // sum of the fluid particles' masses (is the geometry the same at every level?)
  std::string integrator;
  double alpha = 0;
  std::string label() const;      // "dx 0.005 m, dt 1e-04 s" or "dx 0.005 m, CFL 0.2"
};

struct Plan {
  Refine refine = Refine::Both;
  double ratio = 2;
  bool from_scenes = false;  // the levels are the user's scene files
  std::vector<LevelSpec> levels;
  double formal_order = 2;
  std::string formal_order_why;
};

// Order of accuracy of an integrator in time (verlet 2, variational 2 at alpha = 1/2 and 1 otherwise, ...).
double integrator_order(const std::string& type, double alpha);

// Plans `levels` levels: from one scene, refined by `ratio` from the coarsest spacing (--dx or the scene's);
// from several scenes, one level each. Each level's scene is parsed with its --set and its particles are
// sampled (counts and fluid mass). InputError (exit 2) names the scene and key when a level cannot be built
// (e.g. a `points` body refined in dx). With `scaled_from` (one-scene studies) nothing is sampled: counts are
// scaled from that level's (the budget's candidate plans).
Plan plan_levels(const StudyOptions& o, int levels, double ratio, const LevelSpec* scaled_from = nullptr);

// The level of `base` (same scene, same overrides) with extra --set (ablation variants), sampled again.
LevelSpec variant_level(const LevelSpec& base, const std::vector<std::string>& extra_sets);

// Builds the level's simulation and probes without running it, so that what `varsph run` would refuse (a
// periodic axis too short for the kernel, a probe on a fluid body, ...) is an InputError before any run.
void validate_level(const LevelSpec& level);

// Resolved scene (every default filled in) of a level, as `varsph run` would write it to run.json.
std::string resolved_scene_json(const LevelSpec& level);

// Cost of a level predicted from a measured one: particle-steps scale the measured seconds per fluid
// particle-step; the step count of a CFL scene scales with dt_estimate; memory scales the measured
// resident size above the process's own baseline with the particle count.
struct Measured {
  double wall = 0, cpu = 0, rss_mb = 0;
  long steps = 0;
  std::size_t fluid = 0, boundary = 0;
  double dt_estimate = 0, t_end = 0;
  double baseline_rss_mb = 0;
};
struct Prediction {
  double steps = 0, particle_steps = 0, wall = 0, cpu = 0, rss_mb = 0;
};
Prediction predict_cost(const Measured& m, const LevelSpec& level);

// Resident memory of this process now [MiB] (the baseline of a level run of the same binary).
double current_rss_mb();
// MemAvailable of /proc/meminfo [MiB] (0 if unknown).
double available_memory_mb();

}  // namespace varsph::study
