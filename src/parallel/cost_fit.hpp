#pragma once
// Partition weights from measured cost (parallel.weights.mode = "cost"). The partition weighs a fluid
// particle 4 and a boundary particle 1 by default: counts, not costs. What a particle costs depends on
// the scene (dynamic walls run the continuity pass, dummy walls their own extrapolation pass, repulsive
// walls none) and on the machine. At every balance check each rank reports its busy time B_r since the
// last check (wall time of its steps minus its time in MPI calls) and its owned fluid and boundary counts
// F_r, W_r; the costs per particle are the least-squares fit of
//   B_r ~ c_f F_r + c_w W_r   over the ranks r (and the earlier checks, halved at each new one),
// and the boundary weight becomes fluid_weight c_w / c_f. Every rank holds the same gathered values and
// does the same arithmetic, so every rank computes the same weights (a partition changes no result:
// docs/parallel.md "Same bits on any number of ranks"). The fit needs ranks whose mixes of fluid and
// walls differ; where they do not (all ranks alike, or one rank), the weights stay as they are.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>

namespace varsph::parallel {

class CostFit {
 public:
  // weight of a fluid particle while fitting: fine enough for a ratio to 1/64
  static constexpr std::int32_t kFluidWeight = 64;

  // One balance check: every rank's busy seconds and owned counts (the same arrays on every rank).
  void add(std::span<const double> busy, std::span<const double> fluid, std::span<const double> boundary) {
    for (double* s : {&ff_, &fw_, &ww_, &fb_, &wb_}) *s *= 0.5;  // the load moves: recent checks count most
    for (std::size_t r = 0; r < busy.size(); ++r) {
      const double f = fluid[r], w = boundary[r], b = busy[r];
      ff_ += f * f;
      fw_ += f * w;
      ww_ += w * w;
      fb_ += f * b;
      wb_ += w * b;
    }
  }

  // c_w / c_f from the normal equations, or nothing when the system is ill-conditioned (the ranks' mixes
  // of fluid and walls nearly proportional: |det| below 1e-3 of ff ww) or the fit is not physical.
  std::optional<double> boundary_over_fluid() const {
    const double det = ff_ * ww_ - fw_ * fw_;
    if (!(ff_ > 0 && ww_ > 0) || !(det > 1e-3 * ff_ * ww_)) return std::nullopt;
    const double cf = (fb_ * ww_ - wb_ * fw_) / det;
    const double cw = (ff_ * wb_ - fw_ * fb_) / det;
    if (!(cf > 0) || !std::isfinite(cw)) return std::nullopt;
    return std::clamp(cw / cf, 0.0, 4.0);  // a wall particle at most 4 fluid ones (noise guard)
  }

  // The boundary weight for kFluidWeight per fluid particle, or nothing (keep the current weights).
  std::optional<std::int32_t> boundary_weight() const {
    const auto q = boundary_over_fluid();
    if (!q) return std::nullopt;
    return std::int32_t(std::lround(*q * kFluidWeight));
  }

 private:
  double ff_ = 0, fw_ = 0, ww_ = 0, fb_ = 0, wb_ = 0;
};

}  // namespace varsph::parallel
