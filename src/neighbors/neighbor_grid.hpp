#pragma once
// Cell-linked neighbour search. Particles are counting-sorted by cell, so each occupied cell is one
// contiguous block; for every block we store the (sorted) particle ranges of its 3^D neighbour cells
// with the periodic image shift to apply. Two builders fill the same structure:
//  - a uniform grid over a bounded domain (periodic axes wrap), cell index = linear index, cells of half
//    the support by default (fewer candidate pairs); neighbour cells adjacent along x are merged into
//    one contiguous particle range;
//  - a hash grid for unbounded domains: cells keyed by integer coordinates hashed into buckets.
// The pair loops (physics/pair_loop.hpp) only see blocks and ranges.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/real.hpp"

namespace varsph {

struct CellBlock {
  std::uint32_t begin, end;          // particles [begin, end) lie in this cell (after sorting)
  std::uint32_t nbr_begin, nbr_end;  // their neighbour ranges: ranges()[nbr_begin .. nbr_end)
};
struct NeighborRange {
  std::uint32_t begin, end;  // particle range of one neighbour cell
  std::uint32_t shift;       // index into shifts(): x_j + shift is the image seen from the block
};

template <int D>
class NeighborGrid {
 public:
  struct Options {
    Vec<D> min = Vec<D>::Zero(), max = Vec<D>::Ones();
    std::array<bool, D> periodic{};
    bool hashed = false;  // unbounded domain: hash grid
    Real cell_size = 1;   // >= support radius (+ skin when lists are reused)
    int subdivision = 2;  // uniform grid: cells of cell_size / subdivision, stencil of (2 s + 1)^D cells
  };

  void configure(const Options& opt);

  // Sorting permutation for positions x (new[k] = old[perm[k]]) and the blocks/ranges of the sorted
  // order. The caller permutes its arrays with `perm` before using blocks()/ranges().
  void build(std::span<const Vec<D>> x, std::vector<std::uint32_t>& perm);

  // Wraps a position into the periodic box; returns the shift added (zero on open axes).
  Vec<D> wrap_shift(const Vec<D>& x) const;

  const std::vector<CellBlock>& blocks() const { return blocks_; }
  // Distributed runs (src/parallel/domain.cpp): blocks over owned particles and ranges over owned and
  // ghost particles, built by the decomposition layer for this grid's cells; swapped in (the arguments
  // get the previous vectors back, for reuse).
  void set_topology(std::vector<CellBlock>& blocks, std::vector<NeighborRange>& ranges) {
    blocks_.swap(blocks);
    ranges_.swap(ranges);
  }
  const std::vector<NeighborRange>& ranges() const { return ranges_; }
  const Vec<D>& shift(std::uint32_t id) const { return shifts_[id]; }
  Real cell_size(int axis) const { return cell_[axis]; }
  const std::array<std::int64_t, D>& cells_per_axis() const { return dims_; }
  bool hashed() const { return opt_.hashed; }
  const Options& options() const { return opt_; }

 private:
  using Coord = std::array<std::int64_t, D>;
  Coord coord_of(const Vec<D>& x) const;
  void build_uniform(std::span<const Vec<D>> x, std::vector<std::uint32_t>& perm);
  void build_hashed(std::span<const Vec<D>> x, std::vector<std::uint32_t>& perm);
  std::uint32_t shift_id(const std::array<int, D>& wrap) const;

  Options opt_;
  int m_ = 1;  // stencil half-width in cells
  std::array<std::int64_t, D> dims_{};
  Vec<D> cell_;
  std::vector<Vec<D>> shifts_;  // 3^D images: wrap in {-1,0,1} per axis
  std::vector<CellBlock> blocks_;
  std::vector<NeighborRange> ranges_;
  // scratch reused between builds (no allocation after the first build of a given size)
  std::vector<std::uint64_t> key_;       // hashed: bucket per particle
  std::vector<std::uint32_t> cell_key_;  // uniform: cell per particle
  // uniform: per-cell counts, then (after the scatter) the end of every cell; hashed: per-bucket counts
  std::vector<std::uint32_t> count_;
  std::vector<Coord> coords_;
  std::vector<std::uint32_t> bucket_start_;  // hashed: bucket -> first block
};

}  // namespace varsph
