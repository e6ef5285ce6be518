#pragma once
// `--tolerance`: the cheapest level whose defended error (the bound) meets a tolerance, per quantity and for
// all the quantities a tolerance names, and, where no level meets it, the resolution and cost the observed
// order predicts (docs/study.md).
#include <string>
#include <vector>

#include "study/quantities.hpp"

namespace varsph::study {

struct ToleranceSpec {
  std::string text;       // as given
  std::string pattern;    // quantity name pattern ('*' matches any run of characters); "*" for a bare tolerance
  double value = 0;
  bool relative = false;  // "5%" or a bare number: a fraction of the quantity's scale
};
ToleranceSpec parse_tolerance(const std::string& text);  // InputError naming the text
bool matches(const std::string& pattern, const std::string& name);

struct QuantityVerdict {
  std::string quantity;
  double tolerance = 0;         // absolute, in the quantity's unit
  int cheapest_level = -1;      // -1: no level meets it
  double needed_refined = 0;    // predicted dx (or dt) that would meet it (0: not predictable: no level
                                //   estimate, or a flagged one)
  double needed_cost_factor = 0;  // its cost relative to the finest level (0: not predictable)
};

struct ToleranceResult {
  ToleranceSpec spec;
  std::vector<QuantityVerdict> quantities;
  int cheapest_level = -1;      // meets the tolerance for every matched quantity with an estimate; -1: none
  std::size_t without_estimate = 0;  // matched quantities that have no error estimate
};

// `levels_cost` is each level's cost (e.g. wall seconds); `cost_exponent` how the cost grows as the refined
// parameter shrinks (d + 1 for dx and dt together, d for dx, 1 for dt).
ToleranceResult evaluate_tolerance(const ToleranceSpec& spec, const std::vector<Quantity>& quantities,
                                   const std::vector<double>& refined, double cost_exponent);

}  // namespace varsph::study
