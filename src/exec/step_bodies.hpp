#pragma once
// Per-particle bodies of the device integrator steps (docs/gpu.md). Each line is the host integrator's
// update (src/integrators/) for one particle, with the same equation reference; the test suite runs both
// on the same state and compares (tests/exec/).
#include <cmath>
#include <cstdint>

#include "core/real.hpp"
#include "physics/eos.hpp"

namespace varsph::exec {

constexpr std::int32_t kFluidKind = 0;

// --- equation of state and pass inputs ---------------------------------------------------------------
struct PressureBody {  // p = EOS(rho), seed eq. (11)
  Real* p;
  const Real* rho;
  physics::TaitEos eos;
  VARSPH_HD void operator()(std::size_t i) const { p[i] = eos.pressure(rho[i]); }
};
struct PressureTermBody {  // p / rho^2 once per particle (RatesImpl::pressure_terms)
  Real* out;
  const Real* p;
  const Real* rho;
  VARSPH_HD void operator()(std::size_t i) const { out[i] = p[i] / (rho[i] * rho[i]); }
};
struct VolumeBody {  // m / rho for density diffusion (RatesImpl::volumes)
  Real* out;
  const Real* mass;
  const Real* rho;
  VARSPH_HD void operator()(std::size_t i) const { out[i] = mass[i] / rho[i]; }
};
// rho_out = rho_base + dt drho where the density is integrated (fluid; walls of the dynamic model)
struct DensityStepBody {
  Real* rho_out;
  const Real* rho_base;
  const Real* drho;
  const std::int32_t* kind;
  Real dt;
  bool walls;
  VARSPH_HD void operator()(std::size_t i) const {
    if (kind[i] == kFluidKind || walls) rho_out[i] = rho_base[i] + dt * drho[i];
  }
};

// --- verlet, symplectic_euler ------------------------------------------------------------------------
// v += dt a (seed eq. 61; symplectic Euler v_{n+1} = v_n + dt a_n), x += dt v (eq. 62) on fluid particles
template <int D>
struct KickDriftBody {
  Vec<D>* x;
  Vec<D>* v;
  const Vec<D>* a;
  const std::int32_t* kind;
  Real dt;
  VARSPH_HD void operator()(std::size_t i) const {
    if (kind[i] != kFluidKind) return;
    v[i] += dt * a[i];
    x[i] += dt * v[i];
  }
};

// --- verlet_dsph (integrators/verlet_dsph.hpp: Gomez-Gesteira et al. 2012, Dominguez et al. 2022) -----
template <int D>
struct VerletDsphBody {
  Vec<D>* x;
  Vec<D>* v;
  Real* rho;
  const Vec<D>* a;
  const Real* drho;
  Vec<D>* vm1;
  Real* rhom1;
  const std::int32_t* kind;
  Real dt, half_dt2, step2;
  bool euler, walls_integrate;
  VARSPH_HD void operator()(std::size_t i) const {
    if (kind[i] == kFluidKind) {
      const Vec<D> vn = v[i];
      const Vec<D> vbase = euler ? vn : vm1[i];
      x[i] += dt * vn + half_dt2 * a[i];  // x_{n+1} = x_n + dt v_n + dt^2/2 a_n
      v[i] = vbase + step2 * a[i];        // v_{n+1} = v_{n-1} + 2 dt a_n  (Euler: v_n + dt a_n)
      vm1[i] = vn;
    } else if (!walls_integrate) {
      return;
    }
    const Real rn = rho[i];
    rho[i] = (euler ? rn : rhom1[i]) + step2 * drho[i];  // rho_{n+1} = rho_{n-1} + 2 dt drho_n
    rhom1[i] = rn;
  }
};

// --- variational (integrators/variational.hpp, seed eq. 63-65) ---------------------------------------
// midpoint configuration x + s v of fluid particles (walls stay): eq. (20)-(21), (30)-(31)
template <int D>
struct MidpointBody {
  Vec<D>* mid;
  const Vec<D>* x;
  const Vec<D>* v;
  const std::int32_t* kind;
  Real s;
  VARSPH_HD void operator()(std::size_t i) const { mid[i] = kind[i] == kFluidKind ? Vec<D>(x[i] + s * v[i]) : x[i]; }
};
// eq. (63) in velocity form: v_out = v + dt [(1-alpha) a1 + alpha a2 + Gamma_k] on fluid particles
template <int D>
struct ApplyFBody {
  Vec<D>* v_out;
  const Vec<D>* v;
  const Vec<D>* a1;
  const Vec<D>* a2;
  const Vec<D>* gamma;
  const std::int32_t* kind;
  Real dt, w1, w2;
  VARSPH_HD void operator()(std::size_t i) const {
    v_out[i] = kind[i] == kFluidKind ? Vec<D>(v[i] + dt * (w1 * a1[i] + w2 * a2[i] + gamma[i])) : v[i];
  }
};
// explicit predictor q_{k+1;0} = 2 q_k - q_{k-1} + dt^2 (a2 + Gamma_k): v_it = v + dt (a2 + Gamma_k)
template <int D>
struct PredictorBody {
  Vec<D>* vit;
  const Vec<D>* v;
  const Vec<D>* a2;
  const Vec<D>* gamma;
  const std::int32_t* kind;
  Real dt;
  VARSPH_HD void operator()(std::size_t i) const { vit[i] = kind[i] == kFluidKind ? Vec<D>(v[i] + dt * (a2[i] + gamma[i])) : v[i]; }
};
// accept the iterate: rho_{k,k+1}, p; a; the next a2; v_{k+1/2}; q_{k+1} = q_k + dt v_{k+1/2}
template <int D>
struct AcceptBody {
  Vec<D>* x;
  Vec<D>* v;
  Vec<D>* a;
  const Vec<D>* a1;
  Vec<D>* a2;
  const Vec<D>* vnew;
  const Vec<D>* gamma;
  Real* rho;
  Real* p;
  const Real* rho1;
  const Real* p1;
  const std::int32_t* kind;
  Real w1, w2, dt;
  VARSPH_HD void operator()(std::size_t i) const {
    rho[i] = rho1[i];
    p[i] = p1[i];
    if (kind[i] != kFluidKind) return;
    a[i] = w1 * a1[i] + w2 * a2[i] + gamma[i];
    a2[i] = a1[i];
    v[i] = vnew[i];
    x[i] += dt * v[i];
  }
};

// --- reductions' items (MaxOp / MinIndexOp of loop_bodies.hpp) -----------------------------------------
// |v| and |a| of fluid particles (integrators/time_step_control.cpp cfl_limits)
template <int D>
struct FluidNormBody {
  const Vec<D>* u;
  const std::int32_t* kind;
  VARSPH_HD double operator()(std::size_t i) const { return kind[i] != kFluidKind ? 0.0 : double(u[i].norm()); }
};
// |u|^2 of fluid particles in Real, as the variational integrator takes it
template <int D>
struct FluidSquaredNormBody {
  const Vec<D>* u;
  const std::int32_t* kind;
  VARSPH_HD double operator()(std::size_t i) const { return kind[i] != kFluidKind ? 0.0 : double(u[i].squaredNorm()); }
};
// |u - w|^2 of fluid particles (the fixed-point residual)
template <int D>
struct FluidSquaredDifferenceBody {
  const Vec<D>* u;
  const Vec<D>* w;
  const std::int32_t* kind;
  VARSPH_HD double operator()(std::size_t i) const {
    return kind[i] != kFluidKind ? 0.0 : double((u[i] - w[i]).squaredNorm());
  }
};
// the health check of sim/diagnostics.cpp: index of a fluid particle with a non-finite position,
// velocity or density, outside a closed axis of the domain, or beyond the density-error bound
// The health rules' per-particle test, comparison for comparison sim/health.cpp flag_pass's: a non-finite
// position, velocity or density (any particle); a fluid particle outside a closed axis of the domain, outside
// [rho_lo, rho_hi] or faster than the speed bound. The host's rules then decide (remove, or stop the run).
template <int D>
struct HealthBody {
  const Vec<D>* x;
  const Vec<D>* v;
  const Real* rho;
  const std::int32_t* kind;
  double rho_lo, rho_hi, v2_max;
  double lo[D], hi[D];
  bool periodic[D];
  VARSPH_HD std::uint64_t operator()(std::size_t i) const {
    const std::uint64_t ok = ~std::uint64_t(0);
    const double r = double(rho[i]);
    bool finite = std::isfinite(r);
    for (int a = 0; a < D; ++a) finite = finite && std::isfinite(double(x[i][a])) && std::isfinite(double(v[i][a]));
    if (!finite) return std::uint64_t(i);
    if (kind[i] != kFluidKind) return ok;
    bool bad = r < rho_lo || r > rho_hi || double(v[i].squaredNorm()) > v2_max;
    for (int a = 0; a < D; ++a) bad = bad || (!periodic[a] && (double(x[i][a]) < lo[a] || double(x[i][a]) > hi[a]));
    return bad ? std::uint64_t(i) : ok;
  }
};

}  // namespace varsph::exec
