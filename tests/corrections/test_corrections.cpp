// Kernel corrections (physics/corrections): Shepard reproduces constants at a free surface; CSPM and MLS
// reproduce a linear field and its gradient to round-off on irregular particles, in 2D and 3D.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "../support/real_tolerance.hpp"
#include "kernels/kernel_eval.hpp"
#include "physics/corrections/corrections.hpp"

using namespace varsph;
using namespace varsph::physics;
namespace corr = varsph::physics::corrections;

namespace {

constexpr double kDx = 0.01, kRho0 = 1000;

// A block of n^D particles (a free surface on every side), jittered by `jitter` dx, with masses and
// densities varied by +-`spread` so volumes are irregular too. Sorted by cell, grid built.
template <int D>
struct Block {
  std::vector<Vec<D>> x, v;
  std::vector<Real> rho, p, m;
  std::vector<std::int32_t> kind;
  NeighborGrid<D> grid;
  std::vector<bool> surface;  // within 2 dx of the block's faces

  Block(int n, double jitter, double spread, double support, unsigned seed = 7) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    const int total = D == 2 ? n * n : n * n * n;
    for (int k = 0; k < total; ++k) {
      Vec<D> q;
      int t = k;
      bool surf = false;
      for (int a = 0; a < D; ++a) {
        const int c = t % n;
        t /= n;
        q[a] = Real((c + 0.5 + jitter * u(gen)) * kDx);
        surf |= c < 2 || c >= n - 2;
      }
      x.push_back(q);
      v.push_back(Vec<D>::Zero());
      rho.push_back(Real(kRho0 * (1 + spread * u(gen))));
      p.push_back(0);
      m.push_back(Real(kRho0 * std::pow(kDx, D) * (1 + spread * u(gen))));
      kind.push_back(0);
      surface.push_back(surf);
    }
    typename NeighborGrid<D>::Options o;
    o.hashed = true;
    o.cell_size = Real(support);
    grid.configure(o);
    std::vector<std::uint32_t> perm;
    grid.build(x, perm);
    auto apply = [&](auto& vec) {
      auto t = vec;
      for (std::size_t k = 0; k < perm.size(); ++k) vec[k] = t[perm[k]];
    };
    apply(x); apply(v); apply(rho); apply(p); apply(m); apply(kind); apply(surface);
  }
  ParticleView<D> view() const { return {x, v, rho, p, m, kind}; }
  std::size_t size() const { return x.size(); }
};

template <int D>
corr::Options options(kernels::KernelType k) {
  return {k, 1.2 * kDx, 9.47, false};
}

// Plain SPH estimates (no correction), to show what the corrections change.
template <int D>
void plain_sph(const Block<D>& b, const corr::Options& o, const std::vector<Real>& f, std::vector<Real>& val,
               std::vector<Vec<D>>& grad) {
  const kernels::AnyKernel<D> W(o.kernel, o.h);
  val.assign(b.size(), 0);
  grad.assign(b.size(), Vec<D>::Zero());
  for (std::size_t i = 0; i < b.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j) {
      const Vec<D> xij = b.x[i] - b.x[j];
      const auto s = W(xij.norm());
      const Real V = b.m[j] / b.rho[j];
      val[i] += V * f[j] * s.w;
      grad[i] += V * (f[j] - f[i]) * s.grad_factor * xij;  // antisymmetric form
    }
}

template <int D>
void check_linear(kernels::KernelType kernel, const char* label) {
  const auto o = options<D>(kernel);
  const double support = kernels::AnyKernel<D>(kernel, o.h).support();
  Block<D> b(D == 2 ? 16 : 8, 0.3, 0.2, support);
  Vec<D> g;
  for (int a = 0; a < D; ++a) g[a] = Real(2.0 - 1.3 * a);  // grad f
  std::vector<Real> f(b.size());
  for (std::size_t i = 0; i < b.size(); ++i) f[i] = Real(1.5) + g.dot(b.x[i]);

  std::vector<Vec<D>> cg(b.size()), mg(b.size()), pg;
  std::vector<Real> cv(b.size()), mv(b.size()), pv;
  corr::cspm_gradient<D>(b.grid, b.view(), o, f, cg);
  corr::cspm_value<D>(b.grid, b.view(), o, f, cg, cv);
  corr::mls<D>(b.grid, b.view(), o, f, mv, mg);
  plain_sph(b, o, f, pv, pg);

  double e_cv = 0, e_cg = 0, e_mv = 0, e_mg = 0, e_pv = 0, e_pg = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    e_cv = std::max(e_cv, std::abs(double(cv[i] - f[i])));
    e_mv = std::max(e_mv, std::abs(double(mv[i] - f[i])));
    e_pv = std::max(e_pv, std::abs(double(pv[i] - f[i])));
    e_cg = std::max(e_cg, double((cg[i] - g).norm()));
    e_mg = std::max(e_mg, double((mg[i] - g).norm()));
    e_pg = std::max(e_pg, double((pg[i] - g).norm()));
  }
  std::printf("[linear %dD %s] max error value/gradient: CSPM %.1e/%.1e  MLS %.1e/%.1e  plain SPH %.1e/%.1e "
              "(f ~ 1.5-2, |grad f| = %.2f, %zu irregular particles)\n",
              D, label, e_cv, e_cg, e_mv, e_mg, e_pv, e_pg, double(g.norm()), b.size());
  // round-off of sums of O(100) terms; float: a few epsilon of f ~ 2 for values, and the moment matrix's
  // conditioning (h-scaled differences) for gradients: ~2000 epsilon relative
  const double tol = test::real_tol(1e-10, 32, 2.0), gtol = test::real_tol(1e-10, 2000);
  EXPECT_LT(e_cv, tol);
  EXPECT_LT(e_cg, gtol * g.norm());
  EXPECT_LT(e_mv, tol);
  EXPECT_LT(e_mg, gtol * g.norm());
  // without correction the surface errors are O(1)
  EXPECT_GT(e_pv, 0.1);
  EXPECT_GT(e_pg, 0.1 * g.norm());
}

}  // namespace

TEST(Corrections, ShepardReproducesAConstantAtAFreeSurface) {
  const auto o = options<2>(kernels::KernelType::Gaussian);
  Block<2> b(16, 0.2, 0.2, kernels::AnyKernel<2>(o.kernel, o.h).support());
  const Real c = Real(3.7);
  std::vector<Real> f(b.size(), c), out(b.size()), pv;
  std::vector<Vec<2>> pg;
  corr::shepard<2>(b.grid, b.view(), o, f, out);
  plain_sph(b, o, f, pv, pg);
  double e_sh = 0, e_plain_surface = 0, e_plain_interior = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    e_sh = std::max(e_sh, std::abs(double(out[i] - c)));
    (b.surface[i] ? e_plain_surface : e_plain_interior) =
        std::max(b.surface[i] ? e_plain_surface : e_plain_interior, std::abs(double(pv[i] - c)) / c);
  }
  // Shepard density of particles all at rho0 (uniform masses): rho0 exactly, also at the surface
  Block<2> u(16, 0.2, 0.0, kernels::AnyKernel<2>(o.kernel, o.h).support());
  std::vector<Real> rho(u.size());
  corr::shepard_density<2>(u.grid, u.view(), o, rho);
  double e_rho = 0;
  for (std::size_t i = 0; i < u.size(); ++i) e_rho = std::max(e_rho, std::abs(double(rho[i] / kRho0 - 1)));
  std::printf("[shepard] constant %.1f: max error %.1e; plain SPH relative error surface %.2f interior %.3f; "
              "Shepard density max |rho/rho0 - 1| = %.1e\n",
              double(c), e_sh, e_plain_surface, e_plain_interior, e_rho);
  EXPECT_LT(e_sh, test::real_tol(1e-13, 16) * c);  // float: a few roundings of the normalised sum
  EXPECT_LT(e_rho, test::real_tol(1e-13, 16));
  EXPECT_GT(e_plain_surface, 0.3);  // a surface particle misses about half its neighbours
}

TEST(Corrections, CspmAndMlsReproduceALinearFieldAndItsGradient2D) {
  check_linear<2>(kernels::KernelType::Gaussian, "gaussian");
  check_linear<2>(kernels::KernelType::WendlandC2, "wendland_c2");
}

TEST(Corrections, CspmAndMlsReproduceALinearFieldAndItsGradient3D) {
  check_linear<3>(kernels::KernelType::WendlandC2, "wendland_c2");
  check_linear<3>(kernels::KernelType::CubicSpline, "cubic_spline");
}

TEST(Corrections, TooFewNeighboursFallBackInsteadOfDividingByZero) {
  // two particles on a line in 2D: M and A are singular
  Block<2> b(1, 0, 0, 0.03);
  b.x.push_back(b.x[0] + Vec<2>(Real(kDx), 0));
  b.v.push_back(Vec<2>::Zero()); b.rho.push_back(Real(kRho0)); b.p.push_back(0);
  b.m.push_back(b.m[0]); b.kind.push_back(0);
  std::vector<std::uint32_t> perm;
  b.grid.build(b.x, perm);
  std::vector<Real> f = {1, 2}, v(2);
  std::vector<Vec<2>> g(2);
  const auto o = options<2>(kernels::KernelType::Gaussian);
  if (perm[0] == 1) std::swap(b.x[0], b.x[1]);
  corr::mls<2>(b.grid, b.view(), o, f, v, g);
  corr::cspm_gradient<2>(b.grid, b.view(), o, f, g);
  for (int i = 0; i < 2; ++i) {
    EXPECT_TRUE(std::isfinite(v[i]));
    EXPECT_TRUE(g[i].allFinite());
  }
}
