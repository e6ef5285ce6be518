#pragma once
// Bridge from the scalar passes (physics/passes.hpp) to the vectorised sweep (sweep_args.hpp). A pass is
// covered only if FluidTerms<Pass> is specialised for its exact type: today the continuity pass, the
// acceleration pass and the fused sweep with the tabulated kernel, no / Molteni / Fourtakas diffusion and
// no / artificial viscosity, each with or without laminar viscosity, for the wall models that exist now.
// Any other pass type - a new policy, a new template parameter, the Riemann solver's terms (a vector twin
// measured slower than the scalar code: docs/performance.md), Antuono's delta-SPH, exact kernels, the
// float build - keeps the scalar sweep
// (vector_sweep() returns false). Pairs with a boundary particle always go through the pass's own
// scalar pair(), so wall models never need a vector twin.
#include <cstring>
#include <span>
#include <type_traits>
#include <vector>

#include "kernels/tabulated.hpp"
#include "neighbors/neighbor_grid.hpp"
#include "physics/passes.hpp"
#include "physics/simd/list_cache.hpp"
#include "physics/simd/sweep_args.hpp"

namespace varsph::physics::simd {

template <class Pass>
struct FluidTerms {
  static constexpr bool covered = false;
};

// The table of F and the support radius of a tabulated kernel into the arguments.
template <int D>
void set_kernel(SweepArgs& A, const kernels::Tabulated<D>& W) {
  A.f_table = W.f_table();
  A.table_scale = W.table_scale();
  A.table_intervals = W.kIntervals;
  A.rc2 = double(W.support()) * double(W.support());
}

template <BoundaryModel M>
constexpr bool known_wall_model = M == BoundaryModel::Repulsive || M == BoundaryModel::Dynamic ||
                                  M == BoundaryModel::DummyAdami || M == BoundaryModel::SoftRepulsive;

template <int D, BoundaryModel M, class Diff>
struct FluidTerms<DensityRatePass<D, kernels::Tabulated<D>, M, Diff>> {
  using Pass = DensityRatePass<D, kernels::Tabulated<D>, M, Diff>;
  static constexpr int diffusion = std::is_same_v<Diff, NoDensityDiffusion>     ? 0
                                   : std::is_same_v<Diff, MolteniDiffusion>      ? 1
                                   : std::is_same_v<Diff, FourtakasDiffusion<D>> ? 2
                                                                                 : -1;
  static constexpr bool covered = known_wall_model<M> && diffusion >= 0;
  static const ParticleView<D>& view(const Pass& p) { return p.s; }
  static void fill(SweepArgs& A, const Pass& p) {
    set_kernel(A, p.W);
    A.continuity = true;
    A.diffusion = diffusion;
    A.walls_active = walls_evolve_density<M>;
    A.wall_continuity_vector = walls_evolve_density<M> && walls_in_continuum<M>;
    A.volume = p.volume;
    if constexpr (diffusion > 0) A.diff_coef = p.diff.coef;
    if constexpr (diffusion == 2) {
      A.diff_rho0 = p.diff.rho0;
      A.diff_rho0_over_B = p.diff.rho0_over_B;
      for (int a = 0; a < D; ++a) A.gravity[a] = p.diff.g[a];
    }
  }
  static void add(Real& acc, const double* sums) { acc += sums[0]; }
};

// 0 none, 1 Monaghan's artificial viscosity (each maybe + Morris' laminar viscosity); -1 not covered
template <class Visc>
constexpr int viscosity_kind = std::is_same_v<Visc, NoViscosity> || std::is_same_v<Visc, LaminarViscosity> ? 0
                               : std::is_same_v<Visc, ArtificialViscosity> ||
                                       std::is_same_v<Visc, ArtificialAndLaminarViscosity>
                                   ? 1
                                   : -1;

template <int D, class Visc, BoundaryModel M>
struct FluidTerms<AccelerationPass<D, kernels::Tabulated<D>, Visc, M>> {
  using Pass = AccelerationPass<D, kernels::Tabulated<D>, Visc, M>;
  static constexpr int viscosity = viscosity_kind<Visc>;
  static constexpr bool covered = known_wall_model<M> && viscosity >= 0;
  static const ParticleView<D>& view(const Pass& p) { return p.s; }
  static void fill(SweepArgs& A, const Pass& p) {
    set_kernel(A, p.W);
    A.acceleration = true;
    A.p_over_rho2 = p.p_over_rho2;
    A.viscosity = viscosity;
    if constexpr (viscosity == 1) {
      const ArtificialViscosity& av = p.visc;
      A.av_alpha_c0 = av.alpha * av.c0;
      A.av_beta = av.beta;
      A.av_h = av.h;
      A.av_eps_h2 = av.eps_h2;
    }
    if constexpr (Visc::laminar) {
      const LaminarViscosity& lv = p.visc;
      A.laminar = true;
      A.lam_nu = lv.nu;
      A.lam_eps_h2 = lv.eps_h2;
    }
  }
  static void add(typename Pass::Acc& acc, const double* sums) {
    for (int a = 0; a < D; ++a) acc.a[a] += sums[1 + a];
  }
};

template <int D, class Dens, class Accel>
struct FluidTerms<FusedRatesPass<D, Dens, Accel>> {
  using Pass = FusedRatesPass<D, Dens, Accel>;
  static constexpr bool covered = FluidTerms<Dens>::covered && FluidTerms<Accel>::covered;
  static const ParticleView<D>& view(const Pass& p) { return p.dens.s; }
  static void fill(SweepArgs& A, const Pass& p) {
    FluidTerms<Dens>::fill(A, p.dens);
    FluidTerms<Accel>::fill(A, p.accel);
  }
  static void add(typename Pass::Acc& acc, const double* sums) {
    FluidTerms<Dens>::add(acc.drho, sums);
    if (acc.fluid) FluidTerms<Accel>::add(acc.a, sums);
  }
};

// begin(i) + vector sums + scalar pair() of the other neighbours + end(i): portable code.
template <int D, class Pass>
void finish_particle(const void* p, std::uint32_t i, const double* sums, const NeighbourList& other) {
  const Pass& pass = *static_cast<const Pass*>(p);
  auto acc = pass.begin(i);
  FluidTerms<Pass>::add(acc, sums);
  for (std::uint32_t k = 0; k < other.n; ++k) {
    Vec<D> xij;
    for (int a = 0; a < D; ++a) xij[a] = Real(other.dx[a][k]);
    pass.pair(acc, i, std::size_t(other.j[k]), xij, Real(other.r2[k]));
  }
  pass.end(i, acc);
}

// This thread's scratch, grown to hold `candidates` (never shrinks; no allocation once warm).
SweepScratch* thread_scratch(std::uint32_t candidates);

void run_sweep(Isa isa, const SweepArgs& args);

// Runs `pass` with the vectorised sweep when this build, the chosen ISA and the pass type allow it;
// returns false (nothing done) otherwise, and the caller runs the scalar sweep. `lists`: neighbour lists
// kept between passes over the same configuration (list_cache.hpp), or none.
template <int D, class Pass>
bool vector_sweep(Isa isa, const NeighborGrid<D>& grid, const Pass& pass, ListCache* lists = nullptr) {
  if constexpr (!FluidTerms<Pass>::covered || !std::is_same_v<Real, double>) {
    return false;
  } else {
    if (isa == Isa::Scalar) return false;
    static_assert(sizeof(CellBlock) == 4 * sizeof(std::uint32_t) && sizeof(NeighborRange) == 3 * sizeof(std::uint32_t));
    static_assert(sizeof(Vec<D>) == D * sizeof(double));
    const ParticleView<D>& s = FluidTerms<Pass>::view(pass);
    SweepArgs A{};
    A.dim = D;
    A.blocks = reinterpret_cast<const std::uint32_t*>(grid.blocks().data());
    A.n_blocks = long(grid.blocks().size());
    A.ranges = reinterpret_cast<const std::uint32_t*>(grid.ranges().data());
    A.shifts = grid.shift(0).data();
    A.x = reinterpret_cast<const double*>(s.x.data());
    A.v = reinterpret_cast<const double*>(s.v.data());
    A.mass = s.mass.data();
    A.rho = s.rho.data();
    A.kind = s.kind.data();
    FluidTerms<Pass>::fill(A, pass);  // kernel, terms, per-particle arrays
    A.finish = &finish_particle<D, Pass>;
    A.pass = &pass;
    A.scratch = &thread_scratch;
    if (lists) lists->prepare(A, &grid, grid.generation(), s.x.size(), isa == Isa::Avx512 ? 8 : 4);
    run_sweep(isa, A);
    return true;
  }
}

}  // namespace varsph::physics::simd
