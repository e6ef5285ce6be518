#pragma once
// `--ablate`: the scene with and without a term (or with each alternative of a model), run at one level,
// and each term's effect on every quantity beside that level's discretisation error (docs/study.md).
#include <string>
#include <vector>

#include "study/level_plan.hpp"
#include "study/quantities.hpp"

namespace varsph::study {

struct AblationVariant {
  std::string term;               // as asked: "physics.xsph", "gravity", "boundary.model", ...
  std::string label;              // "without physics.xsph", "boundary.model = dynamic"
  std::vector<std::string> sets;  // --set of the variant (after the level's own)
  bool alternative = false;       // another value of a setting (model, integrator, KEY=VALUE), not a term on/off
};

// The variants of each --ablate item: a `physics.*` term the scene names is removed, one it does not name is
// added with its defaults; `gravity` is set to zero; `boundary.model`, `integrator.type` (or `integrator`),
// `integrator.alpha` and `physics.density` give one variant per alternative; KEY=VALUE gives exactly that
// variant. Every variant keeps the base level's resolved c0 and repulsive-wall D (both derive from gravity
// when "auto"), so only the term changes. Each variant scene is parsed: a variant that cannot run is an
// InputError naming the --ablate item, except alternatives of a model list, which are dropped with a note.
std::vector<AblationVariant> ablation_variants(const std::vector<std::string>& items, const LevelSpec& base,
                                               std::vector<std::string>& notes);

struct TermEffect {
  std::string quantity;
  double effect = 0;      // |variant - base| (series: the norm of the difference)
  double error = 0;       // estimated discretisation error of the base at this level
  double ratio = 0;       // effect / error
};

struct AblationResult {
  AblationVariant variant;
  LevelRun run;
  std::vector<TermEffect> effects;
  std::string verdict;    // "not needed at this resolution" | "needed" | "essential" | "failed" | "no estimate"
  std::string reason;     // the quantity that decides, or the failure
  double cpu_saving = 0, wall_saving = 0;  // (base - variant) / base
};

// Effect of the variant on every quantity against the discretisation error of level `level` (the level
// both runs share). A term switched off or on: "not needed at this resolution" when every effect is below the
// estimated error, "essential" when one is above 10 x the error or the variant's run fails numerically,
// "needed" between. An alternative setting: "no difference beyond the discretisation error", "differs",
// "differs strongly" (above 10 x), or "fails" (exit 3).
void judge_ablation(AblationResult& a, const LevelRun& base, const std::vector<Quantity>& quantities,
                    std::size_t level, Norm norm);

}  // namespace varsph::study
