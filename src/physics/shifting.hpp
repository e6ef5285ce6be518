#pragma once
// Particle shifting (physics.shifting), a correction of the particle positions after the drift that
// keeps the particle arrangement near-uniform (against the clumping / stretching of the tensile
// instability and at stagnation points). Fick's-law form of Lind et al. (2012, J. Comput. Phys. 231)
// with the diffusion coefficient of Skillen et al. (2013) / DualSPHysics and the anti-clumping term of
// Sun et al. (2017, delta+-SPH):
//   grad C_i = sum_j V_j [1 + R (W_ij / W(dx))^n] grad_i W_ij                 (Lind 2012; Sun 2017)
//   dr_i     = -D_i grad C_i,  D_i = A h |v_i| dt   ("local", Skillen 2013; DualSPHysics, A = 2)
//                              D   = A h max_k |v_k| dt ("max"; Sun 2017's CFL Ma (2h)^2 is A = 4 with CFL = c0 dt / h)
//   |dr_i| <= max_shift dx (a safety cap of this implementation, not in the papers)
//   free surface: div r_i = -sum_j V_j x_ij . grad_i W_ij (= D in the bulk); "zero": dr_i = 0 where
//   div r_i < threshold (DualSPHysics: 1.5 in 2D, 2.75 in 3D); "tangential" (the free-surface rule of
//   Sun et al. 2017's delta+-SPH, eq. 25, with div r as the surface indicator): dr_i = 0 at the surface,
//   dr_i = (I - n n) dr_i in the band threshold <= div r_i < near_threshold below it, n = -grad C / |grad C|
//   the outward normal, so particles slide along the surface and are never pushed through it.
// Only fluid particles are shifted. Neighbours: fluid and boundary particles of every wall model, all with
// V_j = m_j / rho0 (not m_j / rho_j: summation densities are deficient near a free surface, which would
// inflate div r there and hide the surface; rho ~ rho0 in a weakly compressible flow, and a uniform
// lattice still gets dr = 0 by symmetry). Walls count as full neighbours, so a fluid particle next to a wall
// is not drawn into it; with the one-layer repulsive wall the support stays truncated, the residual push
// toward the wall is bounded by the cap and opposed by the wall force). Velocities and densities are not
// re-interpolated to the shifted positions (Lind's Taylor correction is not applied): summation density
// recomputes rho at the new positions; with continuity the density is carried by the particle.
#include <algorithm>
#include <cmath>

#include "core/real.hpp"
#include "physics/particle_view.hpp"

namespace varsph::physics {

struct ShiftingParams {
  bool enabled = false;
  Real A = 2;                  // coefficient A of D = A h |v| dt
  bool global_speed = false;   // "max": max_k |v_k| instead of |v_i|
  Real R = Real(0.2);          // Sun 2017 anti-clumping coefficient (0 = off)
  int n = 4;                   // exponent of W_ij / W(dx)
  bool free_surface_zero = true;  // no shift where div r < threshold
  bool tangential = false;        // Sun 2017: only the tangential part where div r < near_threshold
  Real fs_threshold = Real(1.5);  // 1.5 (2D), 2.75 (3D)
  Real near_threshold = Real(1.75);  // (threshold + D) / 2 by default
  Real max_shift = Real(0.1);     // cap on |dr| in units of dx
};

// One pass over the fluid particles; writes out[i] (zero for boundary particles is not written: the
// caller only applies out to fluid slots). speed_global: max fluid |v| (used when p.global_speed).
template <int D, class Kernel>
struct ShiftingPass {
  const Kernel& W;
  const ParticleView<D>& s;
  ShiftingParams p;
  Real h, dt, rho0, cap, inv_w_dx, speed_global;
  Vec<D>* out;
  struct Acc {
    Vec<D> grad_c;
    Real div_r;
    Vec<D> grad_s;  // sum_j V_j grad_i W_ij, the surface normal's direction ("tangential" mode only)
  };
  bool active(std::size_t i) const { return s.kind[i] == 0; }
  Acc begin(std::size_t) const { return {Vec<D>::Zero(), Real(0), Vec<D>::Zero()}; }
  Real tensile(Real w) const {
    Real f = w * inv_w_dx, fn = 1;
    for (int k = 0; k < p.n; ++k) fn *= f;
    return Real(1) + p.R * fn;  // Sun 2017: 1 + R (W_ij / W(dx))^n
  }
  void pair(Acc& acc, std::size_t, std::size_t j, const Vec<D>& xij, Real r2) const {
    const Real Vj = s.mass[j] / rho0;  // V_j = m_j / rho0 (see above)
    const Real F = W.grad_factor_r2(r2);  // grad_i W_ij = F x_ij
    acc.grad_c += (Vj * F * tensile(W.w_r2(r2))) * xij;  // Lind 2012, with Sun 2017's term
    acc.div_r -= Vj * F * r2;                            // div r_i = -sum_j V_j x_ij . grad_i W_ij
    if (p.tangential) acc.grad_s += (Vj * F) * xij;
  }
  void end(std::size_t i, const Acc& acc) const {
    if (p.free_surface_zero && acc.div_r < p.fs_threshold) {
      out[i] = Vec<D>::Zero();
      return;
    }
    const Real speed = p.global_speed ? speed_global : s.v[i].norm();
    Vec<D> dr = (-p.A * h * speed * dt) * acc.grad_c;  // Skillen 2013: D = A h |v| dt
    if (p.tangential && acc.div_r < p.near_threshold) {
      // n from the plain kernel-gradient sum: the shift itself (with the anti-clumping weights) would give
      // n parallel to dr and remove all of it
      const Real g = acc.grad_s.norm();
      if (g > Real(0)) {
        const Vec<D> n = -acc.grad_s / g;  // outward normal of the free surface
        dr -= dr.dot(n) * n;               // Sun 2017 eq. (25): (I - n n) dr
      }
    }
    const Real len = dr.norm();
    if (len > cap) dr *= cap / len;
    out[i] = dr;
  }
};

}  // namespace varsph::physics
