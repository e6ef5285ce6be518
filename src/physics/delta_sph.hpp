#pragma once
// The delta-SPH density diffusion with renormalised density gradients (Antuono, Colagrossi, Marrone &
// Molteni 2010, Comput. Phys. Commun. 181:532, eq. 10; Marrone et al. 2011, CMAME 200:1526, eq. 7):
//   D_i = delta h c0 sum_j psi_ij . grad_i W_ij V_j,
//   psi_ij = [2 (rho_j - rho_i) - (<grad rho>^L_i + <grad rho>^L_j) . x_ji] x_ji / |x_ji|^2,
//   <grad rho>^L_i = L_i sum_j (rho_j - rho_i) grad_i W_ij V_j,  L_i = [sum_j x_ji (x) grad_i W_ij V_j]^-1
// over fluid neighbours. The gradient correction makes psi vanish for any linear density field, also where
// the support is cut by a free surface or a wall (hydrostatic stratification is not diffused, the defect of
// Molteni & Colagrossi 2009 that Fourtakas et al. 2019 remove with a hydrostatic correction instead). With
// grad_i W = F x_ij: D_i = -delta h c0 sum_j V_j F [2 (rho_j - rho_i) + (g_i + g_j) . x_ij].
// The renormalised gradients need their own neighbour sweep (RenormalisedDensityGradientPass), run before
// every continuity evaluation that uses them. This diffusion is the one of delta-plus-SPH (Sun et al. 2017).
#include <Eigen/Dense>

#include "core/real.hpp"
#include "physics/particle_view.hpp"

namespace varsph::physics {

template <int D>
struct AntuonoDiffusion {
  static constexpr bool enabled = true;
  static constexpr bool uses_pressure = false;
  static constexpr bool uses_gradient = true;
  Real coef;                    // delta h c0
  const Vec<D>* grad = nullptr;  // <grad rho>^L per particle (fluid), from RenormalisedDensityGradientPass
  AntuonoDiffusion(Real delta, Real h, Real c0) : coef(delta * h * c0) {}
  VARSPH_HD Real term_g(std::size_t i, std::size_t j, Real rho_i, Real rho_j, Real Vj, Real F, const Vec<D>& xij) const {
    return -coef * Vj * F * (Real(2) * (rho_j - rho_i) + (grad[i] + grad[j]).dot(xij));  // Antuono 2010 eq. 10
  }
};

// <grad rho>^L_i of every fluid particle (fluid neighbours only). Where the renormalisation matrix is
// singular (a particle with one or two neighbours in a splash) the uncorrected gradient is used.
template <int D, class Kernel>
struct RenormalisedDensityGradientPass {
  const Kernel& W;
  const ParticleView<D>& s;
  const Real* volume;  // V_j = m_j / rho_j
  Vec<D>* out;
  struct Acc {
    Eigen::Matrix<Real, D, D> M;
    Vec<D> g;
  };
  VARSPH_HD bool active(std::size_t i) const { return s.kind[i] == 0; }
  VARSPH_HD Acc begin(std::size_t) const { return {Eigen::Matrix<Real, D, D>::Zero(), Vec<D>::Zero()}; }
  VARSPH_HD void pair(Acc& acc, std::size_t i, std::size_t j, const Vec<D>& xij, Real r2) const {
    if (s.kind[j] != 0) return;
    const Real FV = W.grad_factor_r2(r2) * volume[j];
    acc.M.noalias() -= (FV * xij) * xij.transpose();  // x_ji (x) grad_i W V_j = -F V x_ij x_ij^T
    acc.g += (FV * (s.rho[j] - s.rho[i])) * xij;
  }
  VARSPH_HD void end(std::size_t i, const Acc& acc) const {
    const Real det = acc.M.determinant();
    // well conditioned: |det M| of order 1 in the bulk (M = identity for a full support)
    out[i] = std::abs(det) > Real(1e-3) ? Vec<D>(acc.M.inverse() * acc.g) : acc.g;
  }
};

}  // namespace varsph::physics
