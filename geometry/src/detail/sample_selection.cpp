#include "detail/sample_selection.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>

#include "detail/point_grid.h"

namespace varsph::geometry::detail {
namespace {

// Darts at radius r; candidate i is blocked by the kept fixed points when fixed_distance[i] < r.
// Returns the indices of the kept candidates.
std::vector<int> throw_darts(const std::vector<double>& fixed_distance, const WeightedPoints& cand,
                             const std::vector<int>& order, double r) {
  PointGrid grid(2.0 * r);
  grid.reserve(cand.size() / 8);
  std::vector<int> kept;
  for (int i : order) {
    if (fixed_distance[i] < r || grid.any_within(cand.x[i], r)) continue;
    grid.insert(cand.x[i]);
    kept.push_back(i);
  }
  return kept;
}

}  // namespace

Layer select_samples(const WeightedPoints& fixed, const WeightedPoints& cand,
                     const WeightedPoints& parcels, double dx, int manifold_dim,
                     double fixed_min_distance, bool random_order) {
  Layer out;
  WeightedPoints extra = parcels;  // parcels plus dropped fixed points
  {
    PointGrid grid(2.0 * std::max(fixed_min_distance, 1e-12));
    grid.reserve(fixed.size());
    for (std::size_t i = 0; i < fixed.size(); ++i) {
      if (fixed_min_distance > 0 && grid.any_within(fixed.x[i], fixed_min_distance)) {
        extra.add(fixed.x[i], fixed.n[i], fixed.w[i]);
        continue;
      }
      grid.insert(fixed.x[i]);
      out.x.push_back(fixed.x[i]);
      out.n.push_back(fixed.n[i] * fixed.w[i]);
      out.a.push_back(fixed.w[i]);
    }
  }
  if (cand.size() > 0) {
    std::vector<int> order(cand.size());
    std::iota(order.begin(), order.end(), 0);
    if (random_order) {  // Fisher-Yates with mt19937 (fully specified, so deterministic everywhere)
      std::mt19937 rng(20240611u);
      for (std::size_t i = order.size() - 1; i > 0; --i)
        std::swap(order[i], order[rng() % (i + 1)]);
    }
    const double total = std::accumulate(cand.w.begin(), cand.w.end(), 0.0);
    const long target = std::lround(total / std::pow(dx, manifold_dim));
    // distance of every candidate to the nearest kept fixed point (capped at 2 dx, the largest r)
    std::vector<double> fixed_distance(cand.size(), INFINITY);
    {
      PointGrid fixed_grid(2.0 * dx);
      fixed_grid.reserve(out.x.size());
      for (const auto& p : out.x) fixed_grid.insert(p);
      for (std::size_t i = 0; i < cand.size(); ++i) fixed_distance[i] = fixed_grid.distance_within(cand.x[i]);
    }
    double lo = 0.7 * dx, hi = 2.0 * dx;
    std::vector<int> best = throw_darts(fixed_distance, cand, order, lo);
    if (static_cast<long>(best.size()) > target) {
      long best_err = static_cast<long>(best.size()) - target;
      // bisection until the count is within 0.5 % (or 1) of the target, or r is pinned down to
      // 0.002 dx (the count is not monotonic in r at that scale)
      const long tolerance = std::max(1L, target / 200);
      for (int it = 0; it < 20 && std::labs(best_err) > tolerance && hi - lo > 2e-3 * dx; ++it) {
        const double mid = 0.5 * (lo + hi);
        std::vector<int> k = throw_darts(fixed_distance, cand, order, mid);
        const long err = static_cast<long>(k.size()) - target;
        if (std::labs(err) < std::labs(best_err) || (std::labs(err) == std::labs(best_err) && err > 0)) {
          best_err = err;
          best = k;
        }
        (err > 0 ? lo : hi) = mid;
      }
    }
    for (int i : best) {
      out.x.push_back(cand.x[i]);
      out.n.push_back(Eigen::Vector3d::Zero());
      out.a.push_back(0.0);
    }
    for (std::size_t i = 0; i < cand.size(); ++i) extra.add(cand.x[i], cand.n[i], cand.w[i]);
  }
  if (!out.x.empty() && extra.size() > 0) {
    PointGrid grid(dx);
    grid.reserve(out.x.size());
    for (const auto& p : out.x) grid.insert(p);
    for (std::size_t i = 0; i < extra.size(); ++i) {
      const int j = grid.nearest(extra.x[i]);
      out.a[j] += extra.w[i];
      out.n[j] += extra.w[i] * extra.n[i];
    }
  }
  for (auto& n : out.n) {
    const double l = n.norm();
    if (l > 0) n /= l;
  }
  return out;
}

}  // namespace varsph::geometry::detail
