// The pair terms on small configurations: signs (PAPER-NOTES.md), conservation of linear and angular
// momentum by the pairwise forces, and the repulsive wall (seed eq. 58).
#include <gtest/gtest.h>

#include <random>

#include "../support/real_tolerance.hpp"
#include "physics/rates.hpp"

using namespace varsph;
using namespace varsph::physics;

namespace {

template <int D>
struct Cloud {
  std::vector<Vec<D>> x, v;
  std::vector<Real> rho, p, m;
  std::vector<std::int32_t> kind;
  ParticleView<D> view() const { return {x, v, rho, p, m, kind}; }
  void add(Vec<D> pos, Vec<D> vel, Real r, Real pr, std::int32_t k = 0) {
    x.push_back(pos); v.push_back(vel); rho.push_back(r); p.push_back(pr); m.push_back(Real(0.025)); kind.push_back(k);
  }
};

template <int D>
NeighborGrid<D> grid_for(std::vector<Vec<D>>& x, Real rc, std::vector<std::uint32_t>& perm) {
  NeighborGrid<D> g;
  typename NeighborGrid<D>::Options o;
  o.hashed = true;
  o.cell_size = rc;
  g.configure(o);
  g.build(x, perm);
  return g;
}

template <int D>
void sort_cloud(Cloud<D>& c, const std::vector<std::uint32_t>& perm) {
  auto apply = [&](auto& vec) { auto t = vec; for (std::size_t k = 0; k < perm.size(); ++k) vec[k] = t[perm[k]]; };
  apply(c.x); apply(c.v); apply(c.rho); apply(c.p); apply(c.m); apply(c.kind);
}

PhysicsParams<2> params2(bool viscosity) {
  PhysicsParams<2> p;
  p.kernel = kernels::KernelType::Gaussian;
  p.h = Real(0.006);
  p.c0 = Real(24);
  p.artificial_viscosity = viscosity;
  p.av_alpha = Real(0.1);
  p.wall_D = Real(5.7);
  p.wall_r0 = Real(0.005);
  return p;
}

}  // namespace

TEST(PairTerms, ApproachingPairGainsDensityAndLosesRelativeSpeed) {
  for (bool approaching : {true, false}) {
    Cloud<2> c;
    const Real s = approaching ? Real(1) : Real(-1);
    c.add({0, 0}, {s * Real(0.5), 0}, 1000, 0);  // pressure zero: the viscosity alone acts
    c.add({Real(0.004), 0}, {-s * Real(0.5), 0}, 1000, 0);
    auto rates = make_rates<2>(params2(true));
    std::vector<std::uint32_t> perm;
    auto g = grid_for<2>(c.x, rates->support(), perm);
    sort_cloud(c, perm);
    std::vector<Real> drho(2);
    std::vector<Vec<2>> a(2);
    rates->density_rate(g, c.view(), drho.data());
    rates->acceleration(g, c.view(), a.data());
    const std::size_t left = c.x[0][0] < c.x[1][0] ? 0 : 1, right = 1 - left;
    const Real dv_rel = (a[right] - a[left])[0];  // d/dt of (v_right - v_left)
    if (approaching) {
      EXPECT_GT(drho[0], 0) << "continuity must compress approaching particles (standard sign)";
      EXPECT_GT(drho[1], 0);
      EXPECT_GT(dv_rel, 0) << "artificial viscosity must slow the approach";
    } else {
      EXPECT_LT(drho[0], 0);
      EXPECT_EQ(dv_rel, 0) << "no artificial viscosity for receding pairs";
    }
  }
}

TEST(PairTerms, PairwiseForcesConserveLinearAndAngularMomentum) {
  // random cluster with random pressures and velocities, no gravity, no walls (seed eq. 39)
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  Cloud<2> c;
  for (int i = 0; i < 200; ++i)
    c.add({Real(0.03 * u(rng)), Real(0.03 * u(rng))}, {Real(u(rng)), Real(u(rng))}, Real(1000 + 20 * u(rng)),
          Real(2000 * u(rng)));
  auto rates = make_rates<2>(params2(true));
  std::vector<std::uint32_t> perm;
  auto g = grid_for<2>(c.x, rates->support(), perm);
  sort_cloud(c, perm);
  std::vector<Vec<2>> a(c.x.size());
  rates->acceleration(g, c.view(), a.data());
  Vec<2> P = Vec<2>::Zero();
  double L = 0, scale = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    P += c.m[i] * a[i];
    L += double(c.m[i]) * (double(c.x[i][0]) * double(a[i][1]) - double(c.x[i][1]) * double(a[i][0]));
    scale += double(c.m[i] * a[i].norm());
  }
  ASSERT_GT(scale, 1.0);
  EXPECT_LT(double(P.norm()), test::real_tol(1e-12, 64) * scale);
  EXPECT_LT(std::abs(L), test::real_tol(1e-12, 64) * scale * 0.03);
}

TEST(PairTerms, RepulsiveWallPushesOutwardOnlyInsideR0) {
  Cloud<2> c;
  c.add({0, Real(0.004)}, {0, 0}, 1000, 0);      // fluid 0.8 dx above a wall particle
  c.add({0, 0}, {0, 0}, 1000, 0, 1);             // boundary
  c.add({Real(0.1), Real(0.0052)}, {0, 0}, 1000, 0);  // fluid beyond r0 of the second wall particle
  c.add({Real(0.1), 0}, {0, 0}, 1000, 0, 1);
  auto rates = make_rates<2>(params2(false));
  std::vector<std::uint32_t> perm;
  auto g = grid_for<2>(c.x, rates->support(), perm);
  sort_cloud(c, perm);
  std::vector<Vec<2>> a(c.x.size(), Vec<2>::Zero());
  rates->acceleration(g, c.view(), a.data());
  for (std::size_t i = 0; i < c.x.size(); ++i) {
    if (c.kind[i] != 0) continue;
    if (c.x[i][0] < Real(0.05)) {
      // eq. (58) with x/r^2: D [(r0/r)^12 - (r0/r)^4] / r^2 * r
      const double r = 0.004, q = 0.005 / r;
      EXPECT_NEAR(double(a[i][1]), 5.7 * (std::pow(q, 12) - std::pow(q, 4)) / r, test::real_tol(1e-9, 8) * 5.7 * std::pow(q, 12) / r);
    } else {
      EXPECT_EQ(double(a[i][1]), 0.0);
    }
  }
}
