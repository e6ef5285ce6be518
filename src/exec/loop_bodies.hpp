#pragma once
// The device loops' bodies (docs/gpu.md): one call per thread index, written once and run by the CUDA
// launch (src/exec/cuda/) and by the host launch that emulates its grid/block indexing (host_launch.hpp).
// Each body writes only the slots of its own index: no atomics, results independent of the launch shape.
#include <cstdint>
#include <limits>

#include "core/real.hpp"
#include "exec/grid_view.hpp"

namespace varsph::exec {

// The neighbour loop of physics/pair_loop.hpp for one particle. The maker (pass_makers.hpp) builds the
// pass (a functor with active/begin/pair/end, physics/passes.hpp) over values held in the body, so its
// references point into the body's own copy on the device.
template <int D, class Maker>
struct PairBody {
  GridView<D> g;
  const Vec<D>* x;
  Real rc2;  // support radius squared
  Maker make;
  VARSPH_HD void operator()(std::size_t index) const {
    make.with([&](const auto& pass) {
      const std::uint32_t i = std::uint32_t(index);
      if (!pass.active(i)) return;
      auto acc = pass.begin(i);
      const Vec<D> xi = x[i];
      std::int64_t c[D];
      g.decode(g.key[i], c);
      g.for_each_range(c, [&](std::uint32_t b, std::uint32_t e, const Vec<D>& shift) {
        const Vec<D> xs = xi - shift;
        for (std::uint32_t j = b; j < e; ++j) {
          const Vec<D> xij = xs - x[j];
          const Real r2 = xij.squaredNorm();
          if (r2 < rc2 && j != i) pass.pair(acc, i, j, xij, r2);
        }
      });
      pass.end(i, acc);
    });
  }
};

// --- sort and bin ----------------------------------------------------------------------------------
// Periodic wrap of positions and of the position-like fields that move with them (Simulation::sort_and_bin).
template <int D>
struct WrapBody {
  static constexpr int kMaxPositionLike = 4;
  GridView<D> g;
  Vec<D>* x;
  Vec<D>* position_like[kMaxPositionLike];
  int n_position_like;
  VARSPH_HD void operator()(std::size_t i) const {
    const Vec<D> s = g.wrap_shift(x[i]);
    if (s.squaredNorm() > 0) {
      x[i] += s;
      for (int k = 0; k < n_position_like; ++k) position_like[k][i] += s;
    }
  }
};

// Cell key of every particle and the identity it is sorted with (value = old index).
template <int D>
struct CellKeyBody {
  GridView<D> g;
  const Vec<D>* x;
  std::uint32_t* key;
  std::uint32_t* index;
  VARSPH_HD void operator()(std::size_t i) const {
    key[i] = g.key_of(x[i]);
    index[i] = std::uint32_t(i);
  }
};

// out[k] = in[perm[k]] for a field of `words` 32-bit words per particle, one thread per word.
struct GatherWordsBody {
  const std::uint32_t* in;
  std::uint32_t* out;
  const std::uint32_t* perm;
  std::uint32_t words;
  VARSPH_HD void operator()(std::size_t t) const {
    const std::size_t k = t / words, c = t % words;
    out[t] = in[std::size_t(perm[k]) * words + c];
  }
};

// cell_end from the sorted keys: sorted particle k ends every cell from its own to the next particle's
// (empty cells in between end where the previous particles did); k = 0 also ends the cells before it.
struct CellEndBody {
  const std::uint32_t* key;
  std::uint32_t* cell_end;
  std::uint32_t n;
  std::uint64_t n_cells;
  VARSPH_HD void operator()(std::size_t k) const {
    const std::uint64_t a = key[k];
    const std::uint64_t b = k + 1 < n ? std::uint64_t(key[k + 1]) : n_cells;
    for (std::uint64_t c = a; c < b; ++c) cell_end[c] = std::uint32_t(k + 1);
    if (k == 0)
      for (std::uint64_t c = 0; c < a; ++c) cell_end[c] = 0;
  }
};

// inv[perm[k]] = k (a permutation's inverse; used to re-express saved orders after a download)
struct InvertBody {
  const std::uint32_t* perm;
  std::uint32_t* inv;
  VARSPH_HD void operator()(std::size_t k) const { inv[perm[k]] = std::uint32_t(k); }
};
// out[k] = map[in[k]]
struct ComposeBody {
  const std::uint32_t* map;
  const std::uint32_t* in;
  std::uint32_t* out;
  VARSPH_HD void operator()(std::size_t k) const { out[k] = map[in[k]]; }
};
struct IotaBody {
  std::uint32_t* out;
  VARSPH_HD void operator()(std::size_t k) const { out[k] = std::uint32_t(k); }
};

// --- reductions (order-independent: max and min only, so the result is the same for any launch) -----
struct MaxOp {
  using T = double;
  VARSPH_HD static T identity() { return 0.0; }                    // the quantities reduced are >= 0
  VARSPH_HD static T combine(T a, T b) { return a < b ? b : a; }   // std::max: a NaN on the right is dropped
};
struct MinIndexOp {
  using T = std::uint64_t;
  VARSPH_HD static T identity() { return std::numeric_limits<std::uint64_t>::max(); }
  VARSPH_HD static T combine(T a, T b) { return b < a ? b : a; }
};

}  // namespace varsph::exec
