#pragma once
// Cell-linked neighbour search. Particles are counting-sorted by cell, so each occupied cell is one
// contiguous block; for every block we store the (sorted) particle ranges of its 3^D neighbour cells
// with the periodic image shift to apply. Two builders fill the same structure:
//  - a uniform grid over a bounded domain (periodic axes wrap), cell index = linear index, cells of half
//    the support by default (fewer candidate pairs); neighbour cells adjacent along x are merged into
//    one contiguous particle range;
//  - a hash grid for unbounded domains: cells keyed by integer coordinates hashed into buckets.
// The pair loops (physics/pair_loop.hpp) only see blocks and ranges.
#include <algorithm>
#include <array>
#include <cmath>
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
  // `window` holds the particle range [begin, end) of every cell of the box [lo, lo + ext) of unwrapped
  // cell coordinates that this process sees (its cells and the halo; periodic images included), for
  // for_each_near.
  void set_topology(std::vector<CellBlock>& blocks, std::vector<NeighborRange>& ranges,
                    const std::array<std::int64_t, D>& window_lo, const std::array<std::int64_t, D>& window_ext,
                    std::vector<std::array<std::uint32_t, 2>>& window) {
    blocks_.swap(blocks);
    ranges_.swap(ranges);
    ++generation_;
    window_lo_ = window_lo;
    window_ext_ = window_ext;
    window_.swap(window);
    local_ = true;
  }
  const std::vector<NeighborRange>& ranges() const { return ranges_; }
  // Changes whenever blocks(), ranges() or the cells change (configure, build, set_topology): a cache of
  // anything derived from them is valid only for the generation it was made for.
  std::uint64_t generation() const { return generation_; }
  const Vec<D>& shift(std::uint32_t id) const { return shifts_[id]; }
  Real cell_size(int axis) const { return cell_[axis]; }
  const std::array<std::int64_t, D>& cells_per_axis() const { return dims_; }
  bool hashed() const { return opt_.hashed; }
  const Options& options() const { return opt_; }

  // Visits every particle j within `radius` (<= the configured cell size) of an arbitrary point p
  // (ghost nodes of walls, probes): f(j, x_pj) with x_pj = p - x_j (periodic image applied), in the
  // sorted order. Valid after build() for the sorted positions x.
  template <class F>
  void for_each_near(const Vec<D>& p, std::span<const Vec<D>> x, Real radius, F&& f) const;

 private:
  using Coord = std::array<std::int64_t, D>;
  // Teschner et al. 2003 spatial hash primes
  static std::uint64_t hash_coord(const Coord& c) {
    constexpr std::uint64_t primes[3] = {73856093ULL, 19349663ULL, 83492791ULL};
    std::uint64_t h = 0;
    for (int a = 0; a < D; ++a) h ^= std::uint64_t(c[a]) * primes[a];
    return h;
  }
  Coord coord_of(const Vec<D>& x) const;
  void build_uniform(std::span<const Vec<D>> x, std::vector<std::uint32_t>& perm);
  void sort_serial(std::size_t n, std::int64_t n_cells, std::vector<std::uint32_t>& perm);
  void sort_parallel(std::size_t n, std::int64_t n_cells, std::vector<std::uint32_t>& perm);
  void build_hashed(std::span<const Vec<D>> x, std::vector<std::uint32_t>& perm);
  std::uint32_t shift_id(const std::array<int, D>& wrap) const;

  Options opt_;
  int m_ = 1;  // stencil half-width in cells
  std::array<std::int64_t, D> dims_{};
  Vec<D> cell_;
  std::vector<Vec<D>> shifts_;  // 3^D images: wrap in {-1,0,1} per axis
  std::vector<CellBlock> blocks_;
  std::vector<NeighborRange> ranges_;
  std::uint64_t generation_ = 0;
  // scratch reused between builds (no allocation after the first build of a given size)
  std::vector<std::uint64_t> key_;       // hashed: bucket per particle
  std::vector<std::uint32_t> cell_key_;  // uniform: cell per particle
  // uniform: per-cell counts, then (after the scatter) the end of every cell; hashed: per-bucket counts
  std::vector<std::uint32_t> count_;
  std::uint32_t n_ranges_ = 0;  // neighbour ranges of the last uniform build (shared by a step's team)
  std::vector<Coord> coords_;
  std::vector<std::uint32_t> bucket_start_;  // hashed: bucket -> first block
  // distributed runs (set_topology): the cells this process sees; local_ false after a serial build()
  bool local_ = false;
  std::array<std::int64_t, D> window_lo_{}, window_ext_{};
  std::vector<std::array<std::uint32_t, 2>> window_;
};

template <int D>
template <class F>
void NeighborGrid<D>::for_each_near(const Vec<D>& p, std::span<const Vec<D>> x, Real radius, F&& f) const {
  const Real r2max = radius * radius;
  auto visit_range = [&](std::uint32_t begin, std::uint32_t end, const Vec<D>& shift) {
    const Vec<D> ps = p - shift;  // x_j + shift is the image seen from p
    for (std::uint32_t j = begin; j < end; ++j) {
      const Vec<D> d = ps - x[j];
      if (d.squaredNorm() < r2max) f(j, d);
    }
  };
  if (opt_.hashed) {
    const Coord c = coord_of(p);
    const std::size_t n_buckets = bucket_start_.empty() ? 0 : bucket_start_.size() - 1;
    if (n_buckets == 0) return;
    const int n_off = D == 2 ? 9 : 27;
    for (int o = 0; o < n_off; ++o) {
      int t = o;
      Coord nc;
      for (int a = 0; a < D; ++a) {
        nc[a] = c[a] + (t % 3 - 1);
        t /= 3;
      }
      const std::uint64_t b = hash_coord(nc) & (n_buckets - 1);
      for (std::uint32_t q = bucket_start_[b]; q < bucket_start_[b + 1]; ++q) {
        const CellBlock& blk = blocks_[q];
        if (coord_of(x[blk.begin]) == nc) visit_range(blk.begin, blk.end, Vec<D>::Zero());
      }
    }
    return;
  }
  // uniform grid: the (2m+1)^D stencil around p's cell, rows read from the per-cell ends in count_
  Coord c;
  for (int a = 0; a < D; ++a) {
    const double fl = std::floor(double(p[a] - opt_.min[a]) / double(cell_[a]));
    c[a] = std::int64_t(std::clamp(fl, -double(m_), double(dims_[a] - 1 + m_)));
  }
  auto cell_end = [&](std::uint64_t k) { return count_[k]; };
  auto cell_begin = [&](std::uint64_t k) { return k == 0 ? 0u : count_[k - 1]; };
  const int w = 2 * m_ + 1;
  const int n_cells = D == 2 ? w * w : w * w * w;
  for (int o = 0; o < n_cells; ++o) {
    int t = o;
    std::uint64_t key = 0, mul = 1;
    Vec<D> shift = Vec<D>::Zero();
    bool valid = true;
    for (int a = 0; a < D; ++a) {
      const std::int64_t unwrapped = c[a] + (t % w - m_);
      std::int64_t nc = unwrapped;
      t /= w;
      if (nc < 0 || nc >= dims_[a]) {
        if (!opt_.periodic[a]) { valid = false; break; }
        const int wrap = nc < 0 ? -1 : 1;
        shift[a] = Real(wrap) * (opt_.max[a] - opt_.min[a]);
        nc = (nc + dims_[a]) % dims_[a];
      }
      if (local_) {  // unwrapped coordinate in the window (cells outside it are not on this process)
        const std::int64_t u = unwrapped - window_lo_[a];
        if (u < 0 || u >= window_ext_[a]) { valid = false; break; }
        key += std::uint64_t(u) * mul;
        mul *= std::uint64_t(window_ext_[a]);
        continue;
      }
      key += std::uint64_t(nc) * mul;
      mul *= std::uint64_t(dims_[a]);
    }
    if (valid && local_) visit_range(window_[key][0], window_[key][1], shift);
    else if (valid) visit_range(cell_begin(key), cell_end(key), shift);
  }
}

}  // namespace varsph
