// The decomposition layer's neighbour grid (parallel/domain.hpp) on one rank against the serial grid
// (NeighborGrid::build): the same particles in the same storage order, and every particle visits the
// same neighbours in the same order with the same periodic shift, over several re-sorts of moving
// particles (the order tags carry the serial program's within-cell order). This is what makes a
// distributed run bitwise equal to a serial one; the multi-rank runs are in test_mpi_runs.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>

#include "parallel/domain.hpp"

namespace varsph::parallel {
namespace {

template <int D>
struct Particles {
  ParticleStore store;
  Field<Vec<D>>& x = store.add<Vec<D>>("position");
  Field<Vec<D>>& x_prev = store.add<Vec<D>>("previous_position");  // position-like (wrapped with x)
  Field<std::int64_t>& id = store.add<std::int64_t>("id");
  Field<std::int32_t>& kind = store.add<std::int32_t>("kind");
  Field<Real>& mass = store.add<Real>("mass");
};

template <int D>
void fill(Particles<D>& p, int n, unsigned seed, const Vec<D>& lo, const Vec<D>& hi) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  p.store.resize(std::size_t(n));
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < D; ++a) p.x[std::size_t(i)][a] = Real(lo[a] + (hi[a] - lo[a]) * u(rng));
    p.x_prev[std::size_t(i)] = p.x[std::size_t(i)];
    p.id[std::size_t(i)] = std::int64_t(n - 1 - i);  // ids not in storage order
    p.kind[std::size_t(i)] = u(rng) < 0.2 ? 1 : 0;
    p.mass[std::size_t(i)] = Real(1);
  }
}

// For every particle (by id): the ids and shifts of its candidate neighbours in visiting order.
template <int D>
std::vector<std::vector<std::tuple<std::int64_t, std::uint32_t, bool>>> visits(const NeighborGrid<D>& g,
                                                                              const Particles<D>& p, Real rc) {
  std::int64_t n_ids = 0;
  for (const auto& b : g.blocks()) n_ids += b.end - b.begin;
  std::vector<std::vector<std::tuple<std::int64_t, std::uint32_t, bool>>> out(static_cast<std::size_t>(n_ids));
  for (const auto& b : g.blocks())
    for (std::uint32_t i = b.begin; i < b.end; ++i) {
      auto& v = out[std::size_t(p.id[i])];
      for (std::uint32_t r = b.nbr_begin; r < b.nbr_end; ++r) {
        const auto nr = g.ranges()[r];
        for (std::uint32_t j = nr.begin; j < nr.end; ++j) {
          const Vec<D> d = p.x[i] - g.shift(nr.shift) - p.x[j];
          v.emplace_back(p.id[j], nr.shift, d.squaredNorm() < rc * rc);
        }
      }
    }
  return out;
}

template <int D>
void compare_over_steps(std::array<bool, D> periodic, unsigned seed) {
  const Real rc = Real(0.1);
  typename NeighborGrid<D>::Options o;
  o.min = Vec<D>::Zero();
  o.max = Vec<D>::Ones();
  o.max[0] = Real(1.5);
  o.periodic = periodic;
  o.cell_size = rc;
  Vec<D> lo = o.min, hi = o.max;
  for (int a = 0; a < D; ++a)
    if (!periodic[a]) {  // some particles outside a bounded axis: binned into the border cell
      lo[a] -= Real(0.05);
      hi[a] += Real(0.05);
    }
  const int n = D == 2 ? 3000 : 6000;
  Particles<D> serial, dist;
  fill(serial, n, seed, lo, hi);
  fill(dist, n, seed, lo, hi);
  NeighborGrid<D> gs, gd;
  gs.configure(o);
  gd.configure(o);
  Domain<D> domain(std::make_shared<SerialCommunicator>(), DomainOptions{});
  domain.attach(dist.store, {"position", "id", "kind", "mass"});
  domain.adopt(dist.store, 0);
  std::vector<Field<Vec<D>>*> position_like{&dist.x_prev};
  std::vector<std::uint32_t> perm;
  std::mt19937 rng(seed + 1);
  std::normal_distribution<double> step(0, 0.02);
  for (int s = 0; s < 6; ++s) {
    // serial: wrap, counting sort, permute (Simulation::sort_and_bin in one process)
    for (std::size_t i = 0; i < serial.store.size(); ++i) {
      const Vec<D> w = gs.wrap_shift(serial.x[i]);
      serial.x[i] += w;
      serial.x_prev[i] += w;
    }
    gs.build(serial.x.data, perm);
    serial.store.permute(perm);
    domain.rebin(dist.store, gd, position_like);
    ASSERT_EQ(domain.owned(), std::size_t(n));
    ASSERT_EQ(domain.ghosts(), 0u);
    for (std::size_t i = 0; i < std::size_t(n); ++i) {
      ASSERT_EQ(dist.id[i], serial.id[i]) << "storage order differs at row " << i << ", sort " << s;
      ASSERT_EQ(dist.x[i], serial.x[i]);
      ASSERT_EQ(dist.x_prev[i], serial.x_prev[i]);
    }
    const auto a = visits(gs, serial, rc), b = visits(gd, dist, rc);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) ASSERT_EQ(a[k], b[k]) << "particle id " << k << ", sort " << s;
    // move both the same way (positions identical bit for bit), some particles across periodic faces
    for (std::size_t i = 0; i < std::size_t(n); ++i) {
      Vec<D> d;
      for (int a = 0; a < D; ++a) d[a] = Real(step(rng));
      serial.x[i] += d;
      dist.x[i] += d;
    }
  }
}

TEST(DomainOneRank, SameNeighboursInTheSameOrderAsTheSerialGrid2D) {
  compare_over_steps<2>({false, false}, 11);
  compare_over_steps<2>({true, false}, 12);
  compare_over_steps<2>({true, true}, 13);
}

TEST(DomainOneRank, SameNeighboursInTheSameOrderAsTheSerialGrid3D) {
  compare_over_steps<3>({false, false, false}, 21);
  compare_over_steps<3>({true, true, true}, 22);
  compare_over_steps<3>({false, true, false}, 23);
}

TEST(DomainOneRank, HashGridIsRefused) {
  typename NeighborGrid<2>::Options o;
  o.hashed = true;
  o.cell_size = Real(0.1);
  NeighborGrid<2> g;
  g.configure(o);
  Particles<2> p;
  fill<2>(p, 10, 1, Vec<2>(Vec<2>::Zero()), Vec<2>(Vec<2>::Ones()));
  Domain<2> domain(std::make_shared<SerialCommunicator>(), DomainOptions{});
  domain.attach(p.store, {"position"});
  domain.adopt(p.store, 0);
  std::vector<Field<Vec<2>>*> none;
  EXPECT_THROW(domain.rebin(p.store, g, none), std::exception);
}

}  // namespace
}  // namespace varsph::parallel
