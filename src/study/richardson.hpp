#pragma once
// Observed order of convergence, Richardson extrapolation and the error of each level, with the flags that
// make such an estimate untrustworthy (docs/study.md). Pure arithmetic on per-level values; no I/O.
#include <string>
#include <vector>

namespace varsph::study {

// What the analysis of one quantity over the levels found. Levels are ordered coarsest first.
struct OrderEstimate {
  double order = 0.0 / 0.0;         // observed order p of the three finest levels (NaN: not computable)
  double order_used = 0.0 / 0.0;    // p used for the extrapolation and the errors (clamped, see richardson())
  double order_fit = 0.0 / 0.0;     // least-squares slope of log|difference| against log h over all level pairs
  std::vector<double> orders;       // p of every consecutive triple (coarse to fine), 4+ levels
  double extrapolated = 0.0 / 0.0;  // Richardson estimate of the converged value
  std::vector<double> error;        // estimated |value_k - converged| per level (NaN: not estimable)
  std::vector<double> bound;        // safety x error: what the study defends (GCI-style band)
  double safety = 3.0;              // 1.25 when the estimate is trusted, 3 otherwise (Roache 1998)
  std::vector<std::string> flags;   // plain-language reasons not to trust the estimate (empty: trusted)
  std::vector<std::string> notes;   // information that does not reduce trust (e.g. no change between levels)
  bool trusted() const { return flags.empty(); }
};

// Order p from the differences of three levels, fine-first notation of Celik et al. 2008 (J. Fluids Eng.
// 130, 078001, eq. 3-4): e21 = phi2 - phi1 (fine pair), e32 = phi3 - phi2 (coarse pair), r21 = h2/h1,
// r32 = h3/h2. Returns the signed solution of p ln r21 = ln|e32/e21| + ln((r21^p - s)/(r32^p - s)),
// s = sign(e32/e21): negative when the differences grow under refinement (divergence).
double three_level_order(double e21, double e32, double r21, double r32);

// Least-squares slope of log(y) against log(x) over the finite positive pairs (NaN if fewer than two).
double log_log_slope(const std::vector<double>& x, const std::vector<double>& y);

// Scalar quantity: values phi (per level, coarsest first, NaN where a level failed) at step sizes h
// (decreasing). `formal_order` is the scheme's (2 for dx refinement, the integrator's for dt); differences
// at or below `noise` count as no change. With three or more levels the three finest give p; trusted when the
// convergence is monotone and 0.5 <= p <= formal + 1, then p_used = min(p, formal) (Roache 1998: never
// extrapolate with more than the formal order) and safety 1.25. Otherwise the flags say why, the errors
// come from the level differences with the formal order (or the largest difference for oscillation) and
// the safety is 3.
OrderEstimate richardson(const std::vector<double>& h, const std::vector<double>& phi, double formal_order,
                         double noise);

// Whole time series: d[k] = ||f_k - f_{k+1}|| (norm of the difference of consecutive levels on a common
// time grid, size levels - 1). The order comes from the norms (monotone by construction); the caller
// builds the extrapolated series f1 + (f1 - f2) / (r21^p_used - 1) and the per-level errors from it.
// Returns p, p_used, flags and safety; `error`/`bound` hold the finest level's estimate only.
OrderEstimate richardson_of_differences(const std::vector<double>& h, const std::vector<double>& d,
                                        double formal_order, double noise);

}  // namespace varsph::study
