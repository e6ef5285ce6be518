#pragma once
// What the vectorised pair sweep (physics/simd/) reads: raw arrays, the kernel table, the switches of the
// fluid-fluid terms, and the portable finisher that runs every other pair through the scalar pass. Plain
// data only (no Eigen, no std containers), because the ISA translation units that read it are compiled
// with -mavx2 / -mavx512f and must not instantiate any inline function the portable code also uses.
#include <cstdint>

namespace varsph::physics::simd {

// Instruction sets the sweep is compiled for; the best one the CPU has is picked at run time.
enum class Isa : int { Scalar = 0, Avx2 = 1, Avx512 = 2 };

// One particle's compacted neighbour list: index j, x_ij = x_i - x_j (periodic image applied) per axis, r^2.
struct NeighbourList {
  std::int32_t* j;
  double* dx[3];
  double* r2;
  std::uint32_t n;
};

// Per-thread scratch: the candidates of one cell block (structure of arrays, padded to whole packs) and
// the two lists of the particle at hand: neighbours whose terms the vector code computes, and the others
// (handed to the scalar pass).
struct SweepScratch {
  double* cx[3];       // candidate positions seen from the block (x_j + periodic shift)
  double* cid;         // candidate index j as a double (self test without int compares)
  double* cwall;       // 1 for a boundary candidate, 0 for fluid
  std::int32_t* cj;    // candidate index j
  NeighbourList vec;   // terms computed by the vector code
  NeighbourList other; // terms computed by the scalar pass (finisher)
};

struct SweepArgs {
  int dim;
  // neighbour structure (NeighborGrid): blocks {begin, end, nbr_begin, nbr_end}, ranges {begin, end, shift}
  const std::uint32_t* blocks;
  long n_blocks;
  const std::uint32_t* ranges;
  const double* shifts;  // dim values per periodic image
  // particles (x and v: dim values per particle)
  const double* x;
  const double* v;
  const double* mass;
  const double* rho;
  const double* p_over_rho2;  // acceleration: p / rho^2 per particle
  const double* volume;       // density diffusion: m / rho per particle
  const std::int32_t* kind;   // 0 fluid
  // kernel gradient factor F (grad_i W = F x_ij) tabulated in r^2: F = t[k] + (u - k)(t[k+1] - t[k]),
  // u = min(r^2 scale, intervals), t[intervals] = t[intervals + 1] = 0 (kernels::Tabulated)
  const double* f_table;
  double table_scale;
  int table_intervals;
  double rc2;  // support radius squared
  // the fluid-fluid terms of the pass
  bool continuity;    // drho_i/dt (DensityRatePass)
  bool acceleration;  // symmetric pressure term (AccelerationPass)
  int diffusion;      // 0 none, 1 Molteni & Colagrossi 2009, 2 Fourtakas et al. 2019
  int viscosity;      // 0 none, 1 Monaghan 1992 artificial viscosity
  bool laminar;       // + Morris 1997 laminar viscosity
  bool walls_only;            // no fluid-fluid terms: fluid particles hand their wall pairs to the finisher
  bool walls_active;          // boundary particles run the pass (dynamic walls' continuity)
  bool wall_continuity_vector;  // ... and their pair terms are the plain continuity sum (vector code)
  double diff_coef, diff_rho0, diff_rho0_over_B, gravity[3];
  double av_alpha_c0, av_beta, av_h, av_eps_h2;
  double lam_nu, lam_eps_h2;  // physics/laminar_viscosity.hpp
  // portable finisher: pass.begin(i), the vector sums added (sums[0] drho, sums[1..dim] acceleration),
  // pass.pair() for every pair in `other`, pass.end(i)
  void (*finish)(const void* pass, std::uint32_t i, const double* sums, const NeighbourList& other);
  const void* pass;
  SweepScratch* (*scratch)(std::uint32_t candidates);  // this thread's scratch, for up to that many candidates
  // neighbour lists kept between passes over the same configuration (physics/simd/list_cache.hpp): 0 none,
  // 1 store every fluid particle's two lists, 2 take them from the store instead of the candidate test
  int list_mode;
  void* lists;
  void (*store_lists)(void* lists, std::uint32_t i, const NeighbourList& vec, const NeighbourList& other);
  void (*load_lists)(const void* lists, std::uint32_t i, NeighbourList& vec, NeighbourList& other);
};

// The sweeps, one per instruction set (sweep_avx2.cpp, sweep_avx512.cpp).
void sweep_avx2(const SweepArgs& args);
void sweep_avx512(const SweepArgs& args);

}  // namespace varsph::physics::simd
