#pragma once
// The one place that owns the neighbour loop. Physics passes are functors with
//   Acc  begin(i)                                  per-particle accumulator
//   void pair(Acc&, i, j, x_ij, r2)                x_ij = x_i - x_j (periodic image applied), r2 = |x_ij|^2
//   void end(i, const Acc&)                        writes only particle i's slot
// so results do not depend on the thread count (each particle sums its pairs in the same order).
#include <span>

#include "core/real.hpp"
#include "core/team.hpp"
#include "neighbors/neighbor_grid.hpp"

namespace varsph {

template <int D, class Pass>
void for_each_particle_pairs(const NeighborGrid<D>& grid, std::span<const Vec<D>> x, Real support,
                             Pass& pass) {
  const auto& blocks = grid.blocks();
  const auto& ranges = grid.ranges();
  const Real rc2 = support * support;
  team_for_dynamic(long(blocks.size()), [&](long b) {
    const CellBlock blk = blocks[std::size_t(b)];
    for (std::uint32_t i = blk.begin; i < blk.end; ++i) {
      if (!pass.active(i)) continue;
      auto acc = pass.begin(i);
      const Vec<D> xi = x[i];
      for (std::uint32_t r = blk.nbr_begin; r < blk.nbr_end; ++r) {
        const NeighborRange nr = ranges[r];
        const Vec<D> xs = xi - grid.shift(nr.shift);
        for (std::uint32_t j = nr.begin; j < nr.end; ++j) {
          const Vec<D> xij = xs - x[j];
          const Real r2 = xij.squaredNorm();
          if (r2 < rc2 && j != i) pass.pair(acc, i, j, xij, r2);
        }
      }
      pass.end(i, acc);
    }
  });
}

// Parallel loop over particles, each writing its own slot (a worksharing loop inside a step's region).
template <class F>
void for_each_particle(std::size_t n, F&& f) {
  team_for(long(n), [&](long i) { f(std::size_t(i)); });
}

}  // namespace varsph
