#pragma once
// `varsph study`: runs a scene at a sequence of resolutions (each level a child `varsph run`), measures
// each level's cost, estimates every quantity's discretisation error, optionally ablates terms, and writes
// DIR/study.json, study.csv, levels.csv, report.md, series/ and plots/ (docs/study.md).
#include <filesystem>
#include <string>
#include <vector>

#include "study/ablation.hpp"
#include "study/level_plan.hpp"
#include "study/quantities.hpp"
#include "study/study_options.hpp"
#include "study/tolerance.hpp"

namespace varsph::study {

struct BudgetReport {
  bool active = false;
  double budget_seconds = 0;
  std::string choice;                 // what was chosen and why
  double predicted_wall = 0, predicted_cpu = 0;  // whole study, predicted after the coarsest level
  double actual_wall = 0, actual_cpu = 0;        // sum over the runs
  std::vector<std::string> rejected;  // plans that did not fit (or did not fit in memory)
};

struct StudyResult {
  StudyOptions options;
  Plan plan;
  std::filesystem::path dir;
  std::vector<LevelRun> levels;
  std::vector<Prediction> predicted;  // per level, from the coarsest level's measured cost (level 0: measured)
  BudgetReport budget;
  std::vector<Window> windows;
  Norm norm = Norm::L2;
  std::vector<Quantity> quantities;
  int ablation_level = -1;
  std::vector<AblationResult> ablations;
  std::vector<Prediction> ablation_predicted;
  std::vector<ToleranceResult> tolerances;
  std::vector<std::string> notes;     // study-wide observations (geometry, failures, skipped variants)
  std::string plots;                  // what became of the plots
  std::string started, finished;
  double study_wall = 0;
  double load_start = 0, load_end = 0;
  int exit_code = 0;
};

// Runs the whole study; returns the exit code (0; 3 if a level failed numerically; 130/143 interrupted).
int run_study(const StudyOptions& o);

}  // namespace varsph::study
