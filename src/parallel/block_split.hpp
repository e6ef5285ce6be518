#pragma once
// A neighbour grid's blocks split in two grids over the same cells, the same particle order and the same
// periodic shifts: part 0 holds the blocks a predicate picks, part 1 the others, each block with its own
// neighbour ranges in their order. A pair sweep over part 0 and then over part 1 computes for every
// particle exactly what one sweep over the whole grid computes (the pair loop is a gather: a particle's
// sum depends on its block's ranges only). Distributed runs pick the blocks whose stencil holds no ghost
// (interior) to sweep them while the halo refresh is in flight (halo_rates.hpp); the fast test
// test_split_sweep checks the equality bit for bit on one process with any predicate.
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "neighbors/neighbor_grid.hpp"

namespace varsph::parallel {

template <int D>
class BlockSplit {
 public:
  // Splits `grid`'s blocks: pick(block) true -> part(0), false -> part(1). No allocation once warm.
  template <class Pick>
  void build(const NeighborGrid<D>& grid, Pick&& pick) {
    source_ = &grid;
    source_generation_ = grid.generation();
    // two passes (classify and count, then copy) so that the copy is plain stores into sized arrays
    const auto& blocks = grid.blocks();
    const NeighborRange* ranges = grid.ranges().data();
    side_.resize(blocks.size());
    std::size_t nb[2] = {0, 0}, nr[2] = {0, 0};
    for (std::size_t q = 0; q < blocks.size(); ++q) {
      const int k = pick(blocks[q]) ? 0 : 1;
      side_[q] = std::uint8_t(k);
      ++nb[k];
      nr[k] += blocks[q].nbr_end - blocks[q].nbr_begin;
    }
    CellBlock* bo[2];
    NeighborRange* ro[2];
    for (int k = 0; k < 2; ++k) {
      blocks_[k].resize(nb[k]);
      ranges_[k].resize(nr[k]);
      bo[k] = blocks_[k].data();
      ro[k] = ranges_[k].data();
    }
    std::uint32_t used[2] = {0, 0};
    for (std::size_t q = 0; q < blocks.size(); ++q) {
      const int k = side_[q];
      const CellBlock& b = blocks[q];
      const std::uint32_t m = b.nbr_end - b.nbr_begin;
      *bo[k]++ = {b.begin, b.end, used[k], used[k] + m};
      std::copy(ranges + b.nbr_begin, ranges + b.nbr_end, ro[k] + used[k]);
      used[k] += m;
    }
    const std::array<std::int64_t, D> none{};
    for (int k = 0; k < 2; ++k) {
      part_[k].configure(grid.options());  // cells and periodic shifts of the source grid (cheap)
      window_.clear();  // no point queries on a part: for_each_near belongs to the whole grid
      part_[k].set_topology(blocks_[k], ranges_[k], none, none, window_);
      // set_topology gave back the part's previous vectors: reused at the next build
    }
    interior_particles_ = 0;
    for (const CellBlock& b : part_[0].blocks()) interior_particles_ += b.end - b.begin;
  }

  // True when the split was made from `grid` as it is now (same object, same blocks and ranges).
  bool made_from(const NeighborGrid<D>& grid) const {
    return source_ == &grid && source_generation_ == grid.generation();
  }
  const NeighborGrid<D>& part(int k) const { return part_[k]; }
  std::size_t picked_particles() const { return interior_particles_; }  // particles of part(0)'s blocks

 private:
  const NeighborGrid<D>* source_ = nullptr;
  std::uint64_t source_generation_ = 0;
  NeighborGrid<D> part_[2];
  std::vector<CellBlock> blocks_[2];
  std::vector<NeighborRange> ranges_[2];
  std::vector<std::uint8_t> side_;  // part of each block of the source grid
  std::vector<std::array<std::uint32_t, 2>> window_;
  std::size_t interior_particles_ = 0;
};

}  // namespace varsph::parallel
