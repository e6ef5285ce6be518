#pragma once
// The vectorised pair sweep, written once over a pack type P (pack_avx2.hpp, pack_avx512.hpp) and
// included only by the per-ISA translation units. Per cell block: the candidates of its neighbour ranges
// are copied once into structure-of-arrays scratch (positions with the periodic shift applied), padded to
// whole packs. Per particle: the candidate test r^2 < r_c^2, j != i runs on packs and compacts the
// neighbours (index, x_ij, r^2) branch-free into two lists: fluid neighbours of a fluid particle, whose
// terms the vector code computes, and all the others (walls), which the portable finisher hands to the
// scalar pass's own pair() - so every wall model and wall term is the scalar code's, by construction.
// The fluid-fluid terms mirror physics/passes.hpp (DensityRatePass::pair_F, AccelerationPass::pair_F);
// tests/physics/test_simd_sweep.cpp compares both for every covered combination. Each particle sums its
// pairs in lanes in a fixed order, so results do not depend on the thread count; they differ from the
// scalar sweep's by the summation order only.
#include <algorithm>
#include <cstdint>

#include "core/team.hpp"
#include "physics/simd/sweep_args.hpp"

namespace {

using varsph::physics::simd::NeighbourList;
using varsph::physics::simd::SweepArgs;
using varsph::physics::simd::SweepScratch;

constexpr double kFar = 1e150;  // padding candidate: r^2 ~ 1e300 fails every support test

template <class P, int D>
struct Sweep {
  using V = typename P::V;
  using M = typename P::M;
  using I = typename P::I;
  static constexpr int W = P::W;

  // Copies the candidates of block b into the scratch; returns their count (padded to whole packs).
  static std::uint32_t gather_candidates(const SweepArgs& A, const std::uint32_t* blk, SweepScratch& S) {
    std::uint32_t n = 0;
    for (std::uint32_t r = blk[2]; r < blk[3]; ++r) {
      const std::uint32_t* rg = A.ranges + 3 * std::size_t(r);
      const double* sh = A.shifts + D * std::size_t(rg[2]);
      for (std::uint32_t j = rg[0]; j < rg[1]; ++j, ++n) {
        for (int a = 0; a < D; ++a) S.cx[a][n] = A.x[D * std::size_t(j) + a] + sh[a];
        S.cid[n] = double(j);
        S.cwall[n] = A.kind[j] != 0 ? 1.0 : 0.0;
        S.cj[n] = std::int32_t(j);
      }
    }
    const std::uint32_t padded = (n + W - 1) / W * W;
    for (std::uint32_t k = n; k < padded; ++k) {
      for (int a = 0; a < D; ++a) S.cx[a][k] = kFar;
      S.cid[k] = -1;
      S.cwall[k] = 0;
      S.cj[k] = 0;
    }
    return padded;
  }

  static std::uint32_t candidates_of(const SweepArgs& A, const std::uint32_t* blk) {
    std::uint32_t n = 0;
    for (std::uint32_t r = blk[2]; r < blk[3]; ++r) n += A.ranges[3 * std::size_t(r) + 1] - A.ranges[3 * std::size_t(r)];
    return n;
  }

  // Candidate test for particle i; fills S.vec (vector terms) and S.other (scalar finisher). route 0:
  // fluid neighbours to S.vec, walls to S.other (fluid particle); 1: all to S.vec (dynamic wall particle's
  // continuity); 2: all to S.other; 3: walls to S.other, fluid neighbours dropped (walls-only pass).
  static void neighbours(const SweepArgs& A, std::uint32_t i, std::uint32_t nc, SweepScratch& S, int route) {
    V xi[D];
    for (int a = 0; a < D; ++a) xi[a] = P::set1(A.x[D * std::size_t(i) + a]);
    const V rc2 = P::set1(A.rc2), self = P::set1(double(i)), zero = P::zero();
    std::uint32_t nv = 0, no = 0;
    for (std::uint32_t k = 0; k < nc; k += W) {
      V d[D];
      V r2 = zero;
      for (int a = 0; a < D; ++a) {
        d[a] = P::sub(xi[a], P::load(S.cx[a] + k));
        r2 = P::fmadd(d[a], d[a], r2);
      }
      const M in = P::mand(P::lt(r2, rc2), P::neq(P::load(S.cid + k), self));
      M to_vec, to_other;
      if (route == 0) {  // fluid particle: fluid neighbours vector, walls scalar
        const M wall = P::neq(P::load(S.cwall + k), zero);
        to_vec = P::mandnot(wall, in);
        to_other = P::mand(wall, in);
      } else if (route == 1) {  // everything vector
        to_vec = in;
        to_other = P::mandnot(in, in);
      } else if (route == 2) {  // everything scalar
        to_vec = P::mandnot(in, in);
        to_other = in;
      } else {  // walls only
        to_vec = P::mandnot(in, in);
        to_other = P::mand(P::neq(P::load(S.cwall + k), zero), in);
      }
      const unsigned mv = P::bits(to_vec), mo = P::bits(to_other);
      const I j = P::iload(S.cj + k);
      // branch-free for the common list, a (well predicted) branch for the rare one
      P::compress(mv, j, S.vec.j + nv);
      for (int a = 0; a < D; ++a) P::compress(mv, d[a], S.vec.dx[a] + nv);
      P::compress(mv, r2, S.vec.r2 + nv);
      nv += unsigned(P::count(mv));
      if (mo) {
        P::compress(mo, j, S.other.j + no);
        for (int a = 0; a < D; ++a) P::compress(mo, d[a], S.other.dx[a] + no);
        P::compress(mo, r2, S.other.r2 + no);
        no += unsigned(P::count(mo));
      }
    }
    // pad the vector list to whole packs with j = i, x_ij = 0 and r^2 beyond the support: F = 0
    // exactly there, so padding lanes add exact zeros to every term
    for (std::uint32_t k = nv; k < nv + W; ++k) {
      S.vec.j[k] = std::int32_t(i);
      for (int a = 0; a < D; ++a) S.vec.dx[a][k] = 0;
      S.vec.r2[k] = 2 * A.rc2;
    }
    S.vec.n = nv;
    S.other.n = no;
  }

  // F(r^2) by the table: the same interpolation as kernels::Tabulated::grad_factor_r2
  static V grad_factor(const SweepArgs& A, V r2) {
    const V u = P::min(P::mul(r2, P::set1(A.table_scale)), P::set1(double(A.table_intervals)));
    const I k = P::trunc(u);
    const V a = P::sub(u, P::to_real(k));
    const V t0 = P::gather(A.f_table, k), t1 = P::gather(A.f_table + 1, k);
    return P::add(t0, P::mul(a, P::sub(t1, t0)));
  }

  // Pair terms of particle i over S.vec; sums[0] += drho/dt, sums[1..D] += acceleration.
  // CONT: continuity, Monaghan 1992 (standard sign, PAPER-NOTES on seed eq. 67-68): m_j F (v_i - v_j) . x_ij
  // DIFF: + density diffusion (1 Molteni & Colagrossi 2009, 2 Fourtakas et al. 2019)
  // ACC: - m_j (p_i/rho_i^2 + p_j/rho_j^2 [+ Pi_ij, VISC 1: Monaghan 1992 artificial viscosity]) F x_ij (seed eq. 38)
  // LAM: + Morris 1997 laminar viscosity, m_j nu (rho_i + rho_j) F r^2 / (rho_i rho_j (r^2 + eps h^2)) v_ij
  template <bool CONT, bool ACC, int DIFF, int VISC, bool LAM>
  static void terms(const SweepArgs& A, std::uint32_t i, const NeighbourList& L, double* sums) {
    if constexpr (!CONT && !ACC) return;
    constexpr bool need_rho_j = (CONT && DIFF > 0) || (ACC && (VISC > 0 || LAM));
    V vi[D];
    for (int a = 0; a < D; ++a) vi[a] = P::set1(A.v[D * std::size_t(i) + a]);
    const V rho_i = P::set1(A.rho[i]);
    const V pr_i = ACC ? P::set1(A.p_over_rho2[i]) : P::zero();
    V drho = P::zero();
    V acc[D];
    for (int a = 0; a < D; ++a) acc[a] = P::zero();
    for (std::uint32_t k = 0; k < L.n; k += W) {
      const I j = P::iload(L.j + k);
      V x[D];
      for (int a = 0; a < D; ++a) x[a] = P::load(L.dx[a] + k);
      const V r2 = P::load(L.r2 + k);
      const V F = grad_factor(A, r2);
      const V mj = P::gather(A.mass, j);
      const I jd = P::iscale(j, D);
      V vij[D];
      V vx = P::zero();  // v_ij . x_ij
      for (int a = 0; a < D; ++a) {
        vij[a] = P::sub(vi[a], P::gather(A.v + a, jd));
        vx = P::fmadd(vij[a], x[a], vx);
      }
      V rho_j = P::zero();
      if constexpr (need_rho_j) rho_j = P::gather(A.rho, j);
      if constexpr (CONT) {
        drho = P::fmadd(P::mul(mj, F), vx, drho);
        if constexpr (DIFF > 0) {
          V drho_ij = P::sub(rho_j, rho_i);
          if constexpr (DIFF == 2) {  // minus the hydrostatic part, Tait series to a^3 (density_diffusion.hpp)
            V gx = P::zero();
            for (int a = 0; a < D; ++a) gx = P::fmadd(P::set1(A.gravity[a]), x[a], gx);
            const V q = P::mul(P::set1(-A.diff_rho0_over_B), gx);  // rho0 g . x_ji / B
            V poly = P::fmadd(q, P::set1(13.0 / 343.0), P::set1(-3.0 / 49.0));
            poly = P::fmadd(q, poly, P::set1(1.0 / 7.0));
            drho_ij = P::sub(drho_ij, P::mul(P::set1(A.diff_rho0), P::mul(q, poly)));
          }
          const V Vj = P::gather(A.volume, j);
          drho = P::sub(drho, P::mul(P::mul(P::set1(A.diff_coef), drho_ij), P::mul(F, Vj)));
        }
      }
      if constexpr (ACC) {
        V coef = P::add(pr_i, P::gather(A.p_over_rho2, j));
        if constexpr (VISC == 1) {
          // Pi_ij = h v.x (beta h v.x - alpha c0 (r^2 + eps h^2)) 2 / ((r^2 + eps h^2)^2 (rho_i + rho_j)) for v.x < 0
          const V den = P::add(r2, P::set1(A.av_eps_h2));
          const V hvx = P::mul(P::set1(A.av_h), vx);
          const V num = P::mul(hvx, P::sub(P::mul(P::set1(A.av_beta), hvx), P::mul(P::set1(A.av_alpha_c0), den)));
          const V pi = P::div(P::add(num, num), P::mul(P::mul(den, den), P::add(rho_i, rho_j)));
          coef = P::add(coef, P::masked(P::lt(vx, P::zero()), pi));
        }
        const V s = P::mul(P::mul(mj, coef), F);
        for (int a = 0; a < D; ++a) acc[a] = P::fnmadd(s, x[a], acc[a]);
        if constexpr (LAM) {
          const V num = P::mul(P::mul(P::mul(mj, P::set1(A.lam_nu)), P::add(rho_i, rho_j)), P::mul(F, r2));
          const V lam = P::div(num, P::mul(P::mul(rho_i, rho_j), P::add(r2, P::set1(A.lam_eps_h2))));
          for (int a = 0; a < D; ++a) acc[a] = P::fmadd(lam, vij[a], acc[a]);
        }
      }
    }
    sums[0] += P::hsum(drho);
    for (int a = 0; a < D; ++a) sums[1 + a] += P::hsum(acc[a]);
  }

  template <bool CONT, bool ACC, int DIFF, int VISC, bool LAM>
  static void run(const SweepArgs& A) {
    varsph::team_for_dynamic(A.n_blocks, [&](long b) {
      const std::uint32_t* blk = A.blocks + 4 * std::size_t(b);
      SweepScratch& S = *A.scratch(candidates_of(A, blk) + 2 * W);
      std::uint32_t nc = 0;
      bool gathered = false;
      for (std::uint32_t i = blk[0]; i < blk[1]; ++i) {
        const bool fluid = A.kind[i] == 0;
        if (!fluid && !A.walls_active) continue;
        if (!gathered && !(fluid && A.list_mode == 2 && !A.walls_only)) {
          nc = gather_candidates(A, blk, S);
          gathered = true;
        }
        double sums[4] = {0, 0, 0, 0};
        if (A.walls_only) {
          if (!fluid) continue;
          neighbours(A, i, nc, S, 3);
        } else if (fluid) {
          if (A.list_mode == 2) {  // the lists of this configuration, stored by an earlier pass
            NeighbourList vec, other;
            A.load_lists(A.lists, i, vec, other);
            terms<CONT, ACC, DIFF, VISC, LAM>(A, i, vec, sums);
            A.finish(A.pass, i, sums, other);
            continue;
          }
          neighbours(A, i, nc, S, 0);
          if (A.list_mode == 1) A.store_lists(A.lists, i, S.vec, S.other);
          terms<CONT, ACC, DIFF, VISC, LAM>(A, i, S.vec, sums);
        } else if (A.wall_continuity_vector) {
          neighbours(A, i, nc, S, 1);
          terms<true, false, 0, 0, false>(A, i, S.vec, sums);
        } else {
          neighbours(A, i, nc, S, 2);
        }
        A.finish(A.pass, i, sums, S.other);
      }
    });
  }

  // with or without Morris' laminar viscosity beside the other terms
  template <bool CONT, bool ACC, int DIFF, int VISC>
  static void with_laminar(const SweepArgs& A) {
    if (A.laminar) return run<CONT, ACC, DIFF, VISC, true>(A);
    return run<CONT, ACC, DIFF, VISC, false>(A);
  }

  template <int DIFF>
  static void fused_with(const SweepArgs& A) {
    if (A.viscosity == 1) return with_laminar<true, true, DIFF, 1>(A);
    return with_laminar<true, true, DIFF, 0>(A);
  }

  static void dispatch(const SweepArgs& A) {
    if (A.walls_only) return run<false, false, 0, 0, false>(A);
    if (A.continuity && A.acceleration) {
      if (A.diffusion == 0) return fused_with<0>(A);
      if (A.diffusion == 1) return fused_with<1>(A);
      return fused_with<2>(A);
    }
    if (A.continuity) {
      if (A.diffusion == 0) return run<true, false, 0, 0, false>(A);
      if (A.diffusion == 1) return run<true, false, 1, 0, false>(A);
      return run<true, false, 2, 0, false>(A);
    }
    if (A.viscosity == 1) return with_laminar<false, true, 0, 1>(A);
    return with_laminar<false, true, 0, 0>(A);
  }
};

template <class P>
void sweep_with(const SweepArgs& A) {
  if (A.dim == 2) Sweep<P, 2>::dispatch(A);
  else Sweep<P, 3>::dispatch(A);
}

}  // namespace
