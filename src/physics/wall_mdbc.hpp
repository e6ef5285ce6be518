#pragma once
// Modified dynamic boundary condition, mDBC (English, Dominguez, Vacondio, Crespo, Stansby, Lind,
// Chiapponi, Gomez-Gesteira 2022, Comp. Part. Mech. 9:1-15, sec. 2.3). Every boundary particle b has a
// ghost node x_g = x_b + 2 d_b n_b mirrored across the fluid-wall interface into the fluid (d_b: distance
// of b to the interface along its normal n_b). At x_g the fluid density and its gradient come from the
// first-order consistent (kernel-gradient-corrected) interpolation of Liu & Liu 2006:
//   [ sum V_j W_gj        sum V_j W_gj x_jg^T      ] [ rho_g      ]   [ sum m_j W_gj      ]
//   [ sum V_j gradW_gj    sum V_j gradW_gj x_jg^T  ] [ grad rho_g ] = [ sum m_j gradW_gj  ]
// (x_jg = x_j - x_g, V_j = m_j / rho_j, fluid j only), and the boundary particle takes
//   gradient extrapolation (English 2022):           rho_b = rho_g + (x_b - x_g) . grad rho_g
//   or the hydrostatic clone (DualSPHysics 5.4's mDBC pressure cloning, JSphCpu_mdbc.cpp):
//                                                  p_b = p(rho_g) + rho0 (g - a_w) . (x_b - x_g)
// with p_b = EOS(rho_b). Where the ghost node's support is nearly empty or the matrix ill conditioned
// (free surface, splash) the zeroth-order Shepard value sum m_j W / sum V_j W is used, and a dry wall
// never pulls: rho_b >= rho0 there (DualSPHysics' rule for a kernel sum below 0.1). Walls with no fluid
// near their ghost node rest at rho0 (p = 0). The viscous wall velocity is Adami's mirror of the
// Shepard-interpolated ghost-node velocity (no-slip) or its tangential part kept (free-slip).
#include <algorithm>

#include "neighbors/neighbor_grid.hpp"
#include "physics/corrected_interpolation.hpp"
#include "physics/eos.hpp"
#include "physics/particle_view.hpp"
#include "physics/wall_geometry.hpp"
#include "physics/wall_mdbc_mode.hpp"

namespace varsph::physics {

template <int D, class Kernel>
struct MdbcWall {
  const Kernel& W;
  const NeighborGrid<D>& grid;
  const ParticleView<D>& s;
  WallGeometry<D> geo;
  Vec<D> g;  // body acceleration in use (ramped gravity + body force)
  TaitEos eos;
  MdbcExtrapolation mode;
  bool free_slip;
  Real* p_out;
  Real* rho_out;
  Vec<D>* vw_out;

  void operator()(std::size_t b) const {
    if (s.kind[b] == 0) return;
    const Vec<D> n = geo.normal ? geo.normal[b] : Vec<D>::Zero();
    const Real d = geo.distance ? geo.distance[b] : Real(0);
    const Vec<D> xg = s.x[b] + (Real(2) * d) * n;  // ghost node
    const Vec<D> vwall = s.v[b];
    CorrectedInterpolation<D> rho_at(double(W.support()));
    Eigen::Matrix<double, D, 1> vsum = Eigen::Matrix<double, D, 1>::Zero();
    grid.for_each_near(xg, s.x, W.support(), [&](std::uint32_t j, const Vec<D>& xgj) {
      if (s.kind[j] != 0) return;
      const Real r2 = xgj.squaredNorm();
      const double w = double(W.w_r2(r2)), V = double(s.mass[j]) / double(s.rho[j]);
      rho_at.add(xgj, w, double(W.grad_factor_r2(r2)), V, double(s.rho[j]));
      for (int a = 0; a < D; ++a) vsum[a] += V * w * double(s.v[j][a]);
    });
    const auto r = rho_at.solve();
    if (r.empty) {  // no fluid near the ghost node: the wall rests at p = 0
      p_out[b] = eos.pressure(eos.rho0);
      rho_out[b] = eos.rho0;
      vw_out[b] = vwall;
      return;
    }
    // nearly dry node (Shepard value only): a wall never pulls the fluid in (DualSPHysics' rule)
    const double rho_g = r.kernel_sum < CorrectedInterpolation<D>::kSubmerged ? std::max(r.value, double(eos.rho0))
                                                                                : r.value;
    double p;
    if (mode == MdbcExtrapolation::Gradient) {  // English 2022: rho_b = rho_g + (x_b - x_g) . grad rho_g
      const double rho_b = rho_g - 2.0 * double(d) * r.gradient.dot(n.template cast<double>());
      p = double(eos.pressure(Real(rho_b)));
    } else {  // pressure clone: p_b = p_g + rho0 (g - a_w) . (x_b - x_g)
      const Vec<D> ga = g - geo.accel(b);
      p = double(eos.pressure(Real(rho_g))) - 2.0 * double(d) * double(eos.rho0) * double(ga.dot(n));
    }
    p_out[b] = Real(p);
    rho_out[b] = p > -double(eos.B) ? eos.density(Real(p)) : eos.rho0 * Real(1e-3);
    Vec<D> vg;
    for (int a = 0; a < D; ++a) vg[a] = Real(vsum[a] / r.kernel_sum);
    const Vec<D> u = vg - vwall;  // ghost-node fluid velocity relative to the wall
    if (!free_slip) vw_out[b] = vwall - u;  // Adami 2012 eq. (22)-(23) at the ghost node
    else vw_out[b] = vwall + u - (Real(2) * u.dot(n)) * n;
  }
};

}  // namespace varsph::physics
