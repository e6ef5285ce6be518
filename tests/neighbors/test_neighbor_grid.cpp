// Neighbour sets of the cell grid and the hash grid against O(N^2) brute force (both sorted first).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <random>
#include <set>

#include "neighbors/neighbor_grid.hpp"

using namespace varsph;

namespace {

template <int D>
using Pairs = std::vector<std::pair<std::int64_t, std::int64_t>>;

// brute force with minimum image on periodic axes; pairs of original indices (i < j), sorted
template <int D>
Pairs<D> brute_force(const std::vector<Vec<D>>& x, Real rc, const typename NeighborGrid<D>::Options& o) {
  Pairs<D> out;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j) {
      Vec<D> d = x[i] - x[j];
      for (int a = 0; a < D; ++a)
        if (o.periodic[a]) {
          const Real L = o.max[a] - o.min[a];
          d[a] -= L * std::round(d[a] / L);
        }
      if (d.squaredNorm() < rc * rc) out.emplace_back(i, j);
    }
  std::sort(out.begin(), out.end());
  return out;
}

template <int D>
Pairs<D> from_grid(std::vector<Vec<D>> x, Real rc, const typename NeighborGrid<D>::Options& o) {
  NeighborGrid<D> g;
  g.configure(o);
  // wrap into the periodic box first, as the simulation does
  for (auto& p : x) p += g.wrap_shift(p);
  std::vector<std::uint32_t> perm;
  g.build(x, perm);
  std::vector<Vec<D>> xs(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) xs[k] = x[perm[k]];
  std::set<std::pair<std::int64_t, std::int64_t>> seen;
  for (const auto& b : g.blocks())
    for (std::uint32_t i = b.begin; i < b.end; ++i)
      for (std::uint32_t r = b.nbr_begin; r < b.nbr_end; ++r) {
        const auto nr = g.ranges()[r];
        for (std::uint32_t j = nr.begin; j < nr.end; ++j) {
          if (i == j) continue;
          const Vec<D> d = xs[i] - g.shift(nr.shift) - xs[j];
          if (d.squaredNorm() < rc * rc) {
            const auto a = std::int64_t(perm[i]), c = std::int64_t(perm[j]);
            const bool fresh = seen.insert({std::min(a, c), std::max(a, c)}).second;
            // every unordered pair is found from both sides, so each appears exactly twice
            (void)fresh;
          }
        }
      }
  return Pairs<D>(seen.begin(), seen.end());
}

template <int D>
typename NeighborGrid<D>::Options options(Real rc, bool hashed, std::array<bool, D> periodic = {}) {
  typename NeighborGrid<D>::Options o;
  o.min = Vec<D>::Zero();
  o.max = Vec<D>::Ones();
  o.periodic = periodic;
  o.hashed = hashed;
  o.cell_size = rc;
  return o;
}

template <int D>
std::vector<Vec<D>> random_points(int n, unsigned seed, Real lo = 0, Real hi = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<Vec<D>> x(n);
  for (auto& p : x)
    for (int a = 0; a < D; ++a) p[a] = Real(u(rng));
  return x;
}

template <int D>
void expect_same(const std::vector<Vec<D>>& x, Real rc, const typename NeighborGrid<D>::Options& o) {
  const auto ref = brute_force<D>(x, rc, o);
  const auto got = from_grid<D>(x, rc, o);
  EXPECT_EQ(got.size(), ref.size());
  EXPECT_TRUE(got == ref);
}

}  // namespace

TEST(NeighborGrid, RandomPointsBothGrids2D3D) {
  for (bool hashed : {false, true}) {
    expect_same<2>(random_points<2>(800, 1), Real(0.07), options<2>(Real(0.07), hashed));
    expect_same<3>(random_points<3>(600, 2), Real(0.15), options<3>(Real(0.15), hashed));
  }
}

TEST(NeighborGrid, ClusteredPointsAllInOneCell) {
  const auto x = random_points<2>(300, 3, Real(0.50), Real(0.52));
  for (bool hashed : {false, true}) expect_same<2>(x, Real(0.1), options<2>(Real(0.1), hashed));
}

TEST(NeighborGrid, PointsOnCellFaces) {
  // a lattice at exactly the cell size: every point lies on a cell face, pair distances equal rc - eps
  std::vector<Vec<2>> x;
  const Real rc = Real(0.1);
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) x.push_back(Vec<2>(Real(i) * rc, Real(j) * rc));
  for (bool hashed : {false, true}) {
    expect_same<2>(x, rc * Real(1.0000001), options<2>(rc * Real(1.0000001), hashed));
    expect_same<2>(x, rc, options<2>(rc, hashed));  // strictly less than: no lattice pair
  }
}

TEST(NeighborGrid, EmptyAndSingleParticle) {
  for (bool hashed : {false, true}) {
    expect_same<2>({}, Real(0.1), options<2>(Real(0.1), hashed));
    expect_same<3>({Vec<3>(Real(0.5), Real(0.5), Real(0.5))}, Real(0.1), options<3>(Real(0.1), hashed));
  }
}

TEST(NeighborGrid, PeriodicImages) {
  auto x = random_points<2>(500, 4);
  expect_same<2>(x, Real(0.08), options<2>(Real(0.08), false, {true, false}));
  expect_same<2>(x, Real(0.08), options<2>(Real(0.08), false, {true, true}));
  auto y = random_points<3>(500, 5);
  expect_same<3>(y, Real(0.2), options<3>(Real(0.2), false, {true, true, true}));
}

TEST(NeighborGrid, HashGridHandlesUnboundedCoordinates) {
  auto x = random_points<3>(400, 6, Real(-50), Real(-49));
  auto far = random_points<3>(100, 7, Real(1e3), Real(1e3 + 1));
  x.insert(x.end(), far.begin(), far.end());
  expect_same<3>(x, Real(0.3), options<3>(Real(0.3), true));
}

TEST(NeighborGrid, SortIsStableAndAPermutation) {
  const auto x = random_points<2>(1000, 8);
  NeighborGrid<2> g;
  g.configure(options<2>(Real(0.05), false));
  std::vector<std::uint32_t> perm;
  g.build(x, perm);
  std::vector<std::uint32_t> sorted = perm;
  std::sort(sorted.begin(), sorted.end());
  for (std::uint32_t k = 0; k < sorted.size(); ++k) ASSERT_EQ(sorted[k], k);
  // blocks cover [0, n) contiguously
  std::uint32_t next = 0;
  for (const auto& b : g.blocks()) {
    EXPECT_EQ(b.begin, next);
    next = b.end;
  }
  EXPECT_EQ(next, 1000u);
}

// Point queries (wall ghost nodes, probes): every particle within the radius of arbitrary points, inside
// and just outside the domain, on both grids and across periodic axes, against brute force.
template <int D>
void check_point_queries(bool hashed, std::array<bool, D> periodic, unsigned seed) {
  const Real rc = 0.13;
  const auto o = options<D>(rc, hashed, periodic);
  NeighborGrid<D> g;
  g.configure(o);
  auto x = random_points<D>(700, seed);
  std::vector<std::uint32_t> perm;
  g.build(x, perm);
  std::vector<Vec<D>> xs(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) xs[k] = x[perm[k]];
  const auto probes = random_points<D>(60, seed + 1, -0.05, 1.05);
  for (const auto& p : probes) {
    std::set<std::uint32_t> expect, got;
    for (std::uint32_t j = 0; j < xs.size(); ++j) {
      Vec<D> d = p - xs[j];
      for (int a = 0; a < D; ++a)
        if (periodic[a]) d[a] -= std::round(d[a]);  // unit box
      if (d.squaredNorm() < rc * rc) expect.insert(j);
    }
    g.for_each_near(p, xs, rc, [&](std::uint32_t j, const Vec<D>& d) {
      EXPECT_TRUE(got.insert(j).second) << "particle visited twice";
      Vec<D> e = p - xs[j];
      for (int a = 0; a < D; ++a)
        if (periodic[a]) e[a] -= std::round(e[a]);
      EXPECT_NEAR(double((d - e).norm()), 0.0, 1e-6) << "offset is not the nearest image";
    });
    EXPECT_EQ(got, expect);
  }
}

TEST(NeighborGrid, PointQueriesMatchBruteForce) {
  check_point_queries<2>(false, {false, false}, 3);
  check_point_queries<2>(false, {true, false}, 4);
  check_point_queries<3>(false, {false, true, false}, 5);
  check_point_queries<2>(true, {false, false}, 6);
  check_point_queries<3>(true, {false, false, false}, 7);
}

// Above 100k particles the counting sort runs in parallel (atomic histogram and cursors, then each cell
// put back in index order): the permutation, blocks and ranges must be those of the serial sort, for
// unsorted input (first step) and for nearly sorted input (every later step), in 2D and 3D.
template <int D>
void expect_parallel_sort_equals_serial(int n, Real cell) {
  auto x = random_points<D>(n, 21, Real(0.1), Real(0.9));
  for (int pass = 0; pass < 2; ++pass) {
    NeighborGrid<D> serial, parallel;
    serial.configure(options<D>(cell, false));
    parallel.configure(options<D>(cell, false));
    std::vector<std::uint32_t> ps, pp;
    omp_set_num_threads(1);
    serial.build(x, ps);
    omp_set_num_threads(3);
    parallel.build(x, pp);
    omp_set_num_threads(1);
    ASSERT_EQ(ps, pp) << "pass " << pass;
    ASSERT_EQ(serial.blocks().size(), parallel.blocks().size());
    for (std::size_t b = 0; b < serial.blocks().size(); ++b) {
      const auto &s = serial.blocks()[b], &p = parallel.blocks()[b];
      ASSERT_TRUE(s.begin == p.begin && s.end == p.end && s.nbr_begin == p.nbr_begin && s.nbr_end == p.nbr_end) << b;
    }
    ASSERT_EQ(serial.ranges().size(), parallel.ranges().size());
    for (std::size_t r = 0; r < serial.ranges().size(); ++r) {
      const auto &s = serial.ranges()[r], &p = parallel.ranges()[r];
      ASSERT_TRUE(s.begin == p.begin && s.end == p.end && s.shift == p.shift) << r;
    }
    // second pass: the sorted order, slightly moved (what sort_and_bin sees every step)
    std::vector<Vec<D>> moved(x.size());
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-0.3 * double(cell), 0.3 * double(cell));
    for (std::size_t k = 0; k < x.size(); ++k) {
      moved[k] = x[ps[k]];
      for (int a = 0; a < D; ++a) moved[k][a] += Real(u(rng));
    }
    x = moved;
  }
}

TEST(NeighborGrid, ParallelCountingSortEqualsTheSerialOne) {
  expect_parallel_sort_equals_serial<2>(150000, Real(0.004));
  expect_parallel_sort_equals_serial<3>(120000, Real(0.02));
}
