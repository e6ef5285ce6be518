// The device loops' cell grid against the host's (neighbors/neighbor_grid.hpp), run through the host
// launch that emulates the CUDA grid/block indexing (exec/host_launch.hpp): the same cell keys, the same
// stable radix-sort permutation as the counting sort, cell ranges that give every particle the same
// neighbour candidates in the same order with the same periodic image shifts (so a pair sum adds the same
// terms in the same order on both), on random, periodic and degenerate inputs. All exact (integers and
// positions compared bitwise).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "exec/device_run.hpp"
#include "exec/grid_view.hpp"
#include "exec/host_launch.hpp"
#include "exec/loop_bodies.hpp"
#include "neighbors/neighbor_grid.hpp"

using namespace varsph;

namespace {

struct Candidate {
  std::uint32_t j;
  std::vector<Real> shift;
  bool operator==(const Candidate&) const = default;
};

// Candidates of every sorted particle, in visiting order: from the host grid's blocks and ranges ...
template <int D>
std::vector<std::vector<Candidate>> host_candidates(const NeighborGrid<D>& g, std::size_t n) {
  std::vector<std::vector<Candidate>> out(n);
  for (const auto& b : g.blocks())
    for (std::uint32_t i = b.begin; i < b.end; ++i)
      for (std::uint32_t r = b.nbr_begin; r < b.nbr_end; ++r) {
        const auto nr = g.ranges()[r];
        const Vec<D>& s = g.shift(nr.shift);
        for (std::uint32_t j = nr.begin; j < nr.end; ++j) out[i].push_back({j, std::vector<Real>(s.data(), s.data() + D)});
      }
  return out;
}
// ... and from the device view's stencil walk
template <int D>
std::vector<std::vector<Candidate>> device_candidates(const exec::GridView<D>& g, std::size_t n) {
  std::vector<std::vector<Candidate>> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::int64_t c[D];
    g.decode(g.key[i], c);
    g.for_each_range(c, [&](std::uint32_t b, std::uint32_t e, const Vec<D>& s) {
      for (std::uint32_t j = b; j < e; ++j) out[i].push_back({j, std::vector<Real>(s.data(), s.data() + D)});
    });
  }
  return out;
}

template <int D>
void check_same_grid(std::vector<Vec<D>> x, const typename NeighborGrid<D>::Options& o) {
  NeighborGrid<D> host;
  host.configure(o);
  for (auto& p : x) p += host.wrap_shift(p);
  std::vector<std::uint32_t> perm;
  host.build(x, perm);

  // the device path through the host launch: keys, stable radix sort, cell ends
  const std::size_t n = x.size();
  exec::HostLaunch launch;
  exec::GridView<D> g = exec::grid_view_of(host);
  std::vector<std::uint32_t> key_in(n), index_in(n), key(n), dperm(n), cell_end(g.n_cells);
  launch.for_each(n, exec::CellKeyBody<D>{g, x.data(), key_in.data(), index_in.data()});
  int bits = 0;
  while (bits < 32 && (std::uint64_t(1) << bits) < g.n_cells) ++bits;
  launch.sort_pairs(key_in.data(), key.data(), index_in.data(), dperm.data(), n, bits);
  ASSERT_EQ(dperm, perm) << "the radix sort must give the counting sort's permutation";
  if (n > 0) launch.for_each(n, exec::CellEndBody{key.data(), cell_end.data(), std::uint32_t(n), g.n_cells});
  g.key = key.data();
  g.cell_end = cell_end.data();
  for (std::size_t k = 1; k < n; ++k) ASSERT_LE(key[k - 1], key[k]);
  const auto a = host_candidates(host, n), b = device_candidates(g, n);
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(a[i], b[i]) << "candidates of sorted particle " << i;
}

template <int D>
typename NeighborGrid<D>::Options unit_box(Real rc, std::array<bool, D> periodic = {}) {
  typename NeighborGrid<D>::Options o;
  o.min = Vec<D>::Zero();
  o.max = Vec<D>::Ones();
  o.periodic = periodic;
  o.cell_size = rc;
  return o;
}

template <int D>
std::vector<Vec<D>> random_points(int n, unsigned seed, double lo = 0, double hi = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<Vec<D>> x(std::size_t(n), Vec<D>::Zero());
  for (auto& p : x)
    for (int a = 0; a < D; ++a) p[a] = Real(u(rng));
  return x;
}

}  // namespace

TEST(DeviceGrid, RandomPointsMatchTheHostGrid2D) { check_same_grid<2>(random_points<2>(3000, 1), unit_box<2>(Real(0.05))); }
TEST(DeviceGrid, RandomPointsMatchTheHostGrid3D) { check_same_grid<3>(random_points<3>(4000, 2), unit_box<3>(Real(0.1))); }

TEST(DeviceGrid, PeriodicAxesMatchTheHostGrid) {
  check_same_grid<2>(random_points<2>(2000, 3, -0.2, 1.2), unit_box<2>(Real(0.07), {true, false}));
  check_same_grid<2>(random_points<2>(2000, 4), unit_box<2>(Real(0.07), {true, true}));
  check_same_grid<3>(random_points<3>(3000, 5), unit_box<3>(Real(0.12), {true, false, true}));
  check_same_grid<3>(random_points<3>(3000, 6), unit_box<3>(Real(0.12), {true, true, true}));
}

TEST(DeviceGrid, DegenerateInputsMatchTheHostGrid) {
  // particles on cell faces, outside a closed domain (binned to the border), all in one cell, one particle
  std::vector<Vec<2>> faces;
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 40; ++j) faces.push_back(Vec<2>(Real(i) * Real(0.025), Real(j) * Real(0.025)));
  check_same_grid<2>(faces, unit_box<2>(Real(0.05)));
  check_same_grid<2>(random_points<2>(500, 7, -0.5, 1.5), unit_box<2>(Real(0.05)));
  check_same_grid<3>(std::vector<Vec<3>>(50, Vec<3>(Real(0.31), Real(0.32), Real(0.33))), unit_box<3>(Real(0.1)));
  check_same_grid<3>(std::vector<Vec<3>>(1, Vec<3>(Real(0.5), Real(0.5), Real(0.5))), unit_box<3>(Real(0.1)));
}

TEST(DeviceGrid, HostLaunchReductionsAndIndexing) {
  exec::HostLaunch launch;
  // every index of a launch that is not a multiple of the block size is visited exactly once
  const std::size_t n = 3 * exec::HostLaunch::kBlock + 17;
  std::vector<std::uint32_t> hits(n, 0);
  struct Count {
    std::uint32_t* h;
    void operator()(std::size_t i) const { ++h[i]; }
  };
  launch.for_each(n, Count{hits.data()});
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i], 1u) << i;
  // the two-pass reduction over more items than its first pass has threads
  const std::size_t m = exec::HostLaunch::kReduceBlocks * exec::HostLaunch::kBlock * 2 + 5;
  const std::size_t spike = m - 3;  // in the second stride of the last block
  EXPECT_EQ(launch.reduce<exec::MaxOp>(m, [spike](std::size_t i) { return i == spike ? 5.5 : double(i % 1000) * 1e-3; }),
            5.5);
  struct Bad {
    std::uint64_t operator()(std::size_t i) const { return (i % 4099 == 4098) ? std::uint64_t(i) : ~std::uint64_t(0); }
  };
  EXPECT_EQ(launch.reduce<exec::MinIndexOp>(m, Bad{}), 4098u);
  EXPECT_EQ(launch.reduce<exec::MinIndexOp>(10, [](std::size_t) { return ~std::uint64_t(0); }), ~std::uint64_t(0));
}
