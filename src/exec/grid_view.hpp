#pragma once
// The cell grid as the device loops see it (docs/gpu.md): the same uniform grid, cell keys and stencil
// as NeighborGrid (src/neighbors/), described by plain values and two arrays, so one thread per particle
// can walk its neighbour cells:
//   key[i]       cell of (sorted) particle i, x fastest: k = c_x + n_x (c_y + n_y c_z)
//   cell_end[c]  one past the last particle of cell c in the sorted order (cells before c included), so the
//                particles of the consecutive cells c0..c1 of one stencil row are [cell_end[c0-1], cell_end[c1])
// Every formula here is NeighborGrid's, operation for operation (cell of a position, periodic images,
// the order rows and x-runs are visited in), so a particle meets its neighbours in the same order on the
// host and on the device.
#include <cmath>
#include <cstdint>

#include "core/real.hpp"

namespace varsph::exec {

template <int D>
struct GridView {
  Real min[D];          // domain.min [m]
  Real max[D];          // domain.max [m]
  Real len[D];          // max - min [m] (periodic image shift)
  Real cell[D];         // cell size per axis [m]
  std::int64_t dims[D];  // cells per axis
  bool periodic[D];
  int m = 2;            // stencil half-width in cells (NeighborGrid subdivision)
  std::uint64_t n_cells = 0;
  const std::uint32_t* key = nullptr;       // per sorted particle
  const std::uint32_t* cell_end = nullptr;  // per cell

  // NeighborGrid::coord_of for a bounded grid: outside particles go to the border cell.
  VARSPH_HD std::uint32_t key_of(const Vec<D>& x) const {
    std::uint64_t k = 0;
    for (int a = D - 1; a >= 0; --a) {
      double f = std::floor(double(x[a] - min[a]) / double(cell[a]));
      const double top = double(dims[a] - 1);
      f = !(f >= 0.0) ? 0.0 : (f > top ? top : f);  // NaN to cell 0 (the health check stops the run after the step)
      k = k * std::uint64_t(dims[a]) + std::uint64_t(std::int64_t(f));
    }
    return std::uint32_t(k);
  }
  VARSPH_HD void decode(std::uint32_t k, std::int64_t* c) const {
    std::uint64_t r = k;
    for (int a = 0; a < D; ++a) {
      c[a] = std::int64_t(r % std::uint64_t(dims[a]));
      r /= std::uint64_t(dims[a]);
    }
  }
  // NeighborGrid::wrap_shift: the shift that brings x into the periodic box (zero on open axes).
  VARSPH_HD Vec<D> wrap_shift(const Vec<D>& x) const {
    Vec<D> s = Vec<D>::Zero();
    for (int a = 0; a < D; ++a) {
      if (!periodic[a]) continue;
      if (x[a] < min[a]) s[a] = len[a] * std::ceil((min[a] - x[a]) / len[a]);
      else if (x[a] >= max[a]) s[a] = -len[a] * std::floor((x[a] - min[a]) / len[a]);
    }
    return s;
  }
  // Calls f(begin, end, shift) for the particle ranges of the stencil cells around cell c, in
  // NeighborGrid's order: rows (offsets on the axes above x, the first fastest), then within a row the
  // x-run wrapped below 0, the run inside, the run wrapped above n_x - 1. x_j + shift is the image of
  // neighbour j seen from c. Empty ranges are skipped.
  template <class F>
  VARSPH_HD void for_each_range(const std::int64_t* c, F&& f) const {
    const int w = 2 * m + 1;
    const int n_rows = D == 2 ? w : w * w;
    for (int row = 0; row < n_rows; ++row) {
      int wrap[D] = {};
      std::uint64_t row_key = 0;
      bool valid = true;
      int t = row;
      std::uint64_t mul = std::uint64_t(dims[0]);
      for (int a = 1; a < D; ++a) {
        const int d = t % w - m;
        t /= w;
        std::int64_t nc = c[a] + d;
        if (nc < 0 || nc >= dims[a]) {
          if (!periodic[a]) {
            valid = false;
            break;
          }
          wrap[a] = nc < 0 ? -1 : 1;
          nc = (nc + dims[a]) % dims[a];
        }
        row_key += std::uint64_t(nc) * mul;
        mul *= std::uint64_t(dims[a]);
      }
      if (!valid) continue;
      const std::int64_t lo = c[0] - m, hi = c[0] + m, nx = dims[0];
      auto slice = [&](std::int64_t x0, std::int64_t x1, int wx) {
        wrap[0] = wx;
        const std::uint64_t k0 = row_key + std::uint64_t(x0), k1 = row_key + std::uint64_t(x1);
        const std::uint32_t b = k0 == 0 ? 0u : cell_end[k0 - 1], e = cell_end[k1];
        if (b == e) return;
        Vec<D> shift;
        for (int a = 0; a < D; ++a) shift[a] = Real(wrap[a]) * len[a];  // NeighborGrid's image shift
        f(b, e, shift);
      };
      if (lo < 0 && periodic[0]) slice(lo + nx, nx - 1, -1);
      slice(lo > 0 ? lo : 0, hi < nx - 1 ? hi : nx - 1, 0);
      if (hi >= nx && periodic[0]) slice(0, hi - nx, 1);
    }
  }
};

}  // namespace varsph::exec
