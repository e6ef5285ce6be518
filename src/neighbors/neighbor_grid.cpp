#include "neighbors/neighbor_grid.hpp"

#include "core/first_touch.hpp"
#include "core/team.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include <omp.h>

namespace varsph {
namespace {

// Below this many particles the counting sort runs serially (a few microseconds; parallel regions would
// cost more). Both paths produce the same stable order, so the choice never changes results.
constexpr std::size_t kParallelSortMin = 100000;

// In-place exclusive prefix sum of get(k) for k < m, set(k, sum of get(0..k-1)), in parallel with a fixed
// partition by the static schedule: integer sums, so the result is the same for any thread count.
template <class Get, class Set>
std::uint32_t parallel_exclusive_scan(long m, Get&& get, Set&& set) {
  if (m < long(kParallelSortMin) || omp_get_max_threads() == 1) {  // a parallel region costs more here
    std::uint64_t run = 0;
    for (long k = 0; k < m; ++k) {
      const std::uint64_t v = get(k);
      set(k, std::uint32_t(run));
      run += v;
    }
    return std::uint32_t(run);
  }
  std::vector<std::uint64_t> part(std::size_t(omp_get_max_threads()) + 1, 0);
  std::uint64_t total = 0;
#pragma omp parallel
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    const long lo = m * t / nt, hi = m * (t + 1) / nt;
    std::uint64_t sum = 0;
    for (long k = lo; k < hi; ++k) sum += get(k);
    part[std::size_t(t) + 1] = sum;
#pragma omp barrier
#pragma omp single
    {
      for (int q = 0; q < nt; ++q) part[std::size_t(q) + 1] += part[std::size_t(q)];
      total = part[std::size_t(nt)];
    }
    std::uint64_t run = part[std::size_t(t)];
    for (long k = lo; k < hi; ++k) {
      const std::uint64_t v = get(k);
      set(k, std::uint32_t(run));
      run += v;
    }
  }
  return std::uint32_t(total);
}

}  // namespace

template <int D>
void NeighborGrid<D>::configure(const Options& opt) {
  ++generation_;
  opt_ = opt;
  if (!(opt.cell_size > 0)) throw std::invalid_argument("neighbour grid: cell size must be positive");
  m_ = opt.hashed ? 1 : std::max(1, opt.subdivision);
  for (int a = 0; a < D; ++a) {
    const double len = double(opt.max[a] - opt.min[a]);
    if (opt.hashed) {
      if (opt.periodic[a]) throw std::invalid_argument("hash grid: periodic axes need a bounded domain");
      cell_[a] = opt.cell_size;
      dims_[a] = 0;
      continue;
    }
    if (!(len > 0)) throw std::invalid_argument("neighbour grid: empty domain on axis " + std::to_string(a));
    std::int64_t n = std::max<std::int64_t>(1, std::int64_t(std::floor(len * m_ / double(opt.cell_size))));
    if (opt.periodic[a] && n < 2 * m_ + 1)
      throw std::invalid_argument("periodic axis " + std::to_string(a) + " is shorter than " +
                                  std::to_string(2 * m_ + 1) + "/" + std::to_string(m_) +
                                  " support radii; enlarge the domain");
    dims_[a] = n;
    cell_[a] = Real(len / double(n));
  }
  // periodic image shifts: wrap w in {-1, 0, 1} per axis; x_j + shift seen from a block
  shifts_.clear();
  const int n_images = D == 2 ? 9 : 27;
  for (int s = 0; s < n_images; ++s) {
    Vec<D> v = Vec<D>::Zero();
    int t = s;
    for (int a = 0; a < D; ++a) {
      const int w = t % 3 - 1;
      t /= 3;
      v[a] = Real(w) * (opt.max[a] - opt.min[a]);
    }
    shifts_.push_back(v);
  }
}

template <int D>
std::uint32_t NeighborGrid<D>::shift_id(const std::array<int, D>& wrap) const {
  std::uint32_t id = 0, mul = 1;
  for (int a = 0; a < D; ++a) {
    id += std::uint32_t(wrap[a] + 1) * mul;
    mul *= 3;
  }
  return id;
}

template <int D>
typename NeighborGrid<D>::Coord NeighborGrid<D>::coord_of(const Vec<D>& x) const {
  Coord c;
  for (int a = 0; a < D; ++a) {
    const double f = std::floor(double(x[a] - opt_.min[a]) / double(cell_[a]));
    if (opt_.hashed) {
      c[a] = std::int64_t(std::clamp(f, -4.0e15, 4.0e15));
    } else {
      // particles outside a bounded domain are binned into the border cell (the health check flags them)
      c[a] = std::int64_t(std::clamp(f, 0.0, double(dims_[a] - 1)));
    }
  }
  return c;
}

template <int D>
Vec<D> NeighborGrid<D>::wrap_shift(const Vec<D>& x) const {
  Vec<D> s = Vec<D>::Zero();
  for (int a = 0; a < D; ++a) {
    if (!opt_.periodic[a]) continue;
    const Real len = opt_.max[a] - opt_.min[a];
    if (x[a] < opt_.min[a]) s[a] = len * std::ceil((opt_.min[a] - x[a]) / len);
    else if (x[a] >= opt_.max[a]) s[a] = -len * std::floor((x[a] - opt_.min[a]) / len);
  }
  return s;
}

template <int D>
void NeighborGrid<D>::build(std::span<const Vec<D>> x, std::vector<std::uint32_t>& perm) {
  // inside a step's parallel region every thread calls this (core/team.hpp): shared state changes once
  team_single([&] {
    local_ = false;
    ++generation_;
    if (opt_.hashed) build_hashed(x, perm);  // serial
  });
  if (!opt_.hashed) build_uniform(x, perm);
}

// Serial stable counting sort of the cell keys; fills perm, count_ (end of every cell) and blocks_.
template <int D>
void NeighborGrid<D>::sort_serial(std::size_t n, std::int64_t n_cells, std::vector<std::uint32_t>& perm) {
  count_.assign(std::size_t(n_cells) + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++count_[cell_key_[i] + 1];
  for (std::int64_t c = 0; c < n_cells; ++c) count_[c + 1] += count_[c];
  perm.resize(n);
  for (std::size_t i = 0; i < n; ++i) perm[count_[cell_key_[i]]++] = std::uint32_t(i);
  // blocks: occupied cells in cell order (count_[c] is now the end of cell c)
  blocks_.clear();
  std::uint32_t begin = 0;
  for (std::int64_t c = 0; c < n_cells; ++c) {
    const std::uint32_t end = count_[c];
    if (end > begin) blocks_.push_back({begin, end, 0, 0});
    begin = end;
  }
}

// The same sort in parallel, with the same result: atomic histogram, parallel prefix sum, scatter with
// atomic cursors (which leaves the order inside a cell arbitrary), then each cell's few particles put back
// in increasing index order - the stable order. The per-cell array is zeroed (and so first touched) with
// the static schedule; no O(cells) or O(particles) loop is serial.
template <int D>
void NeighborGrid<D>::sort_parallel(std::size_t n, std::int64_t n_cells, std::vector<std::uint32_t>& perm) {
  const long nn = long(n), nc = long(n_cells);
  if (count_.size() != std::size_t(n_cells) + 1) {
    count_.clear();
    count_.shrink_to_fit();
    first_touch_resize(count_, std::size_t(n_cells) + 1);
  }
  std::uint32_t* cnt = count_.data();
  const std::uint32_t* key = cell_key_.data();
#pragma omp parallel for schedule(static)
  for (long c = 0; c <= nc; ++c) cnt[c] = 0;
#pragma omp parallel for schedule(static)
  for (long i = 0; i < nn; ++i) {
#pragma omp atomic update
    ++cnt[key[i]];
  }
  // cnt[c] = first slot of cell c, cnt[n_cells] = n
  parallel_exclusive_scan(nc + 1, [&](long c) { return cnt[c]; }, [&](long c, std::uint32_t at) { cnt[c] = at; });
  first_touch_resize(perm, n);
  std::uint32_t* out = perm.data();
#pragma omp parallel for schedule(static)
  for (long i = 0; i < nn; ++i) {
    std::uint32_t slot;
#pragma omp atomic capture
    slot = cnt[key[i]]++;
    out[slot] = std::uint32_t(i);
  }
  // cnt[c] is now the end of cell c. Blocks: occupied cells in cell order (count per static chunk of
  // cells, prefix over the chunks, fill), and each block's particles sorted by index (stable order).
  const int nt_max = omp_get_max_threads();
  std::vector<std::uint32_t> part(std::size_t(nt_max) + 1, 0);
  auto begin_of = [cnt](long c) { return c == 0 ? 0u : cnt[c - 1]; };
  int teams = 1;
#pragma omp parallel
  {
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    const long lo = nc * t / nt, hi = nc * (t + 1) / nt;
    std::uint32_t occupied = 0;
    for (long c = lo; c < hi; ++c) occupied += cnt[c] > begin_of(c);
    part[std::size_t(t) + 1] = occupied;
#pragma omp single
    teams = nt;
  }
  for (int q = 0; q < teams; ++q) part[std::size_t(q) + 1] += part[std::size_t(q)];
  blocks_.clear();
  first_touch_resize(blocks_, part[std::size_t(teams)]);
#pragma omp parallel
  for (int t = omp_get_thread_num(); t < teams; t += omp_get_num_threads()) {  // the chunks counted above
    const long lo = nc * t / teams, hi = nc * (t + 1) / teams;
    std::uint32_t at = part[std::size_t(t)];
    for (long c = lo; c < hi; ++c) {
      const std::uint32_t b = begin_of(c), e = cnt[c];
      if (e <= b) continue;
      std::uint32_t* p = out + b;
      for (std::uint32_t k = 1; k < e - b; ++k)  // insertion sort: a cell holds a few particles
        for (std::uint32_t q = k; q > 0 && p[q - 1] > p[q]; --q) std::swap(p[q - 1], p[q]);
      blocks_[at++] = {b, e, 0, 0};
    }
  }
}

template <int D>
void NeighborGrid<D>::build_uniform(std::span<const Vec<D>> x, std::vector<std::uint32_t>& perm) {
  const std::size_t n = x.size();
  std::int64_t n_cells = 1;
  for (int a = 0; a < D; ++a) n_cells *= dims_[a];
  // cell keys in 4 bytes per particle, computed in parallel once (the histogram and the scatter read
  // them twice: recomputing the floor per axis there cost 7 % of a 2D step)
  team_single([&] {
    if (n_cells >= std::int64_t(std::numeric_limits<std::uint32_t>::max()))
      throw std::invalid_argument("neighbour grid: " + std::to_string(n_cells) +
                                  " cells exceed a dense grid; use domain.neighbor_search = \"hash\"");
    key_.clear();
    key_.shrink_to_fit();
  });
  first_touch_resize(cell_key_, n);
  team_for(long(n), [&](long i) {
    const Coord c = coord_of(x[std::size_t(i)]);
    std::uint64_t k = 0;
    for (int a = D - 1; a >= 0; --a) k = k * std::uint64_t(dims_[a]) + std::uint64_t(c[a]);
    cell_key_[std::size_t(i)] = std::uint32_t(k);
  });
  // stable counting sort by cell with one per-cell array: count_[c + 1] = particles in cell c, prefix sum
  // (count_[c] = first slot of cell c), scatter with count_[c] as the cursor (count_[c] = end of cell c).
  // Inside a step's region it runs on one thread (the region is used for small cases, where it is serial).
  team_single([&] {
    if (n < kParallelSortMin || omp_get_max_threads() == 1) sort_serial(n, n_cells, perm);
    else sort_parallel(n, n_cells, perm);
  });
  // Neighbour ranges of every block: the stencil cells of one row (fixed offsets on the axes above x)
  // are consecutive cell keys, so their particles are one slice of the sorted order, read from the
  // cell ends in count_: (2m+1)^(D-1) ranges per block (split only where x wraps periodically), in
  // the order of the cell offsets (x fastest). Two parallel passes (count, then fill) so the layout is
  // the same for any thread count.
  const int w = 2 * m_ + 1;
  const int n_rows = D == 2 ? w : w * w;
  auto visit = [&](const CellBlock& b, auto&& emit) {
    const Coord c = coord_of(x[perm[b.begin]]);
    NeighborRange pending{0, 0, 0};
    bool have = false;
    auto push = [&](std::uint32_t begin, std::uint32_t end, std::uint32_t shift) {
      if (begin == end) return;
      if (have && pending.end == begin && pending.shift == shift) {
        pending.end = end;  // contiguous in memory with the previous slice: extend it
      } else {
        if (have) emit(pending);
        pending = {begin, end, shift};
        have = true;
      }
    };
    for (int row = 0; row < n_rows; ++row) {
      std::array<int, D> wrap{};
      std::uint64_t row_key = 0;  // key of cell (0, c_y + dy[, c_z + dz])
      bool valid = true;
      {
        int t = row;
        std::uint64_t mul = std::uint64_t(dims_[0]);
        for (int a = 1; a < D; ++a) {
          const int d = t % w - m_;
          t /= w;
          std::int64_t nc = c[a] + d;
          if (nc < 0 || nc >= dims_[a]) {
            if (!opt_.periodic[a]) { valid = false; break; }
            wrap[a] = nc < 0 ? -1 : 1;  // the neighbour row is the periodic image: x_j seen at x_j -/+ L
            nc = (nc + dims_[a]) % dims_[a];
          }
          row_key += std::uint64_t(nc) * mul;
          mul *= std::uint64_t(dims_[a]);
        }
      }
      if (!valid) continue;
      // x offsets -m..m: at most three runs (wrapped below 0, inside, wrapped above dims-1)
      const std::int64_t lo = c[0] - m_, hi = c[0] + m_, nx = dims_[0];
      auto slice = [&](std::int64_t x0, std::int64_t x1, int wx) {  // cells x0..x1 of this row
        wrap[0] = wx;
        const std::uint64_t k0 = row_key + std::uint64_t(x0), k1 = row_key + std::uint64_t(x1);
        push(k0 == 0 ? 0u : count_[k0 - 1], count_[k1], shift_id(wrap));  // start of x0 .. end of x1
      };
      if (lo < 0 && opt_.periodic[0]) slice(lo + nx, nx - 1, -1);
      slice(std::max<std::int64_t>(lo, 0), std::min<std::int64_t>(hi, nx - 1), 0);
      if (hi >= nx && opt_.periodic[0]) slice(0, hi - nx, 1);
    }
    if (have) emit(pending);
  };
  const long nblk = long(blocks_.size());
  team_for(nblk, [&](long q) {
    std::uint32_t cnt = 0;
    visit(blocks_[std::size_t(q)], [&](const NeighborRange&) { ++cnt; });
    blocks_[std::size_t(q)].nbr_end = cnt;
  });
  team_single([&] {
    n_ranges_ = parallel_exclusive_scan(
        nblk, [&](long q) { return blocks_[std::size_t(q)].nbr_end; },
        [&](long q, std::uint32_t at) {
          CellBlock& b = blocks_[std::size_t(q)];
          b.nbr_end += at;
          b.nbr_begin = at;
        });
  });
  first_touch_resize(ranges_, n_ranges_);
  team_for(nblk, [&](long q) {
    std::uint32_t at = blocks_[std::size_t(q)].nbr_begin;
    visit(blocks_[std::size_t(q)], [&](const NeighborRange& r) { ranges_[at++] = r; });
  });
}

template <int D>
void NeighborGrid<D>::build_hashed(std::span<const Vec<D>> x, std::vector<std::uint32_t>& perm) {
  const std::size_t n = x.size();
  const std::size_t n_buckets = std::max<std::size_t>(64, std::bit_ceil(2 * n + 1));
  coords_.resize(n);
  key_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    coords_[i] = coord_of(x[i]);
    key_[i] = hash_coord(coords_[i]) & (n_buckets - 1);
  }
  count_.assign(n_buckets + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++count_[key_[i] + 1];
  for (std::size_t b = 0; b < n_buckets; ++b) count_[b + 1] += count_[b];
  perm.resize(n);
  bucket_start_.assign(count_.begin(), count_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) perm[bucket_start_[key_[i]]++] = std::uint32_t(i);
  // inside a bucket, group particles of the same cell (stable: ties keep the original order)
  for (std::size_t b = 0; b < n_buckets; ++b) {
    auto first = perm.begin() + count_[b], last = perm.begin() + count_[b + 1];
    if (last - first > 1)
      std::stable_sort(first, last, [&](std::uint32_t p, std::uint32_t q) { return coords_[p] < coords_[q]; });
  }
  // blocks in sorted order; bucket_start_[b] = first block of bucket b
  blocks_.clear();
  bucket_start_.assign(n_buckets + 1, 0);
  for (std::size_t b = 0; b < n_buckets; ++b) {
    bucket_start_[b] = std::uint32_t(blocks_.size());
    for (std::uint32_t s = count_[b]; s < count_[b + 1];) {
      std::uint32_t e = s + 1;
      while (e < count_[b + 1] && coords_[perm[e]] == coords_[perm[s]]) ++e;
      blocks_.push_back({s, e, 0, 0});
      s = e;
    }
  }
  bucket_start_[n_buckets] = std::uint32_t(blocks_.size());
  ranges_.clear();
  const int n_off = D == 2 ? 9 : 27;
  const std::array<int, D> no_wrap{};
  for (auto& blk : blocks_) {
    const Coord c = coords_[perm[blk.begin]];
    blk.nbr_begin = std::uint32_t(ranges_.size());
    for (int o = 0; o < n_off; ++o) {
      int t = o;
      Coord nc;
      for (int a = 0; a < D; ++a) {
        nc[a] = c[a] + (t % 3 - 1);
        t /= 3;
      }
      const std::uint64_t b = hash_coord(nc) & (n_buckets - 1);
      for (std::uint32_t q = bucket_start_[b]; q < bucket_start_[b + 1]; ++q)
        if (coords_[perm[blocks_[q].begin]] == nc)
          ranges_.push_back({blocks_[q].begin, blocks_[q].end, shift_id(no_wrap)});
    }
    blk.nbr_end = std::uint32_t(ranges_.size());
  }
}

template class NeighborGrid<2>;
template class NeighborGrid<3>;

}  // namespace varsph
