#pragma once
// Kernel corrections of the foundation notes ("CSPM normalisation", "Shepard correction", "MLS correction"),
// as operators on a configuration: each reads the particle view (volumes V_j = m_j / rho_j) and a field,
// and writes the corrected estimate for every participating particle. The neighbour grid must be valid
// for view.x. Sums include the particle itself (x_ii = 0).
//   Shepard (zeroth order; Shepard 1968): f_i = sum_j V_j f_j W_ij / sum_j V_j W_ij — reproduces constants.
//   Shepard density re-initialisation (Colagrossi & Landrini 2003): rho_i = sum_j m_j W_ij / sum_j V_j W_ij.
//   CSPM gradient (Chen et al. 1999; Bonet & Lok 1999): grad f_i = L_i sum_j V_j (f_j - f_i) grad_i W_ij with
//     L_i = M_i^{-T}, M_i^{ab} = sum_j V_j (x_j - x_i)^a grad_i^b W_ij — reproduces linear fields' gradients.
//   CSPM value, first order (Chen et al. 1999, Taylor series kept to the first derivative):
//     f_i = [sum_j V_j f_j W_ij - grad f_i . sum_j V_j (x_j - x_i) W_ij] / sum_j V_j W_ij with the CSPM
//     gradient — reproduces linear fields. (The notes' W/sum V W value alone is the Shepard one.)
//   MLS, first order, 2D and 3D (Dilts 1999; Belytschko et al. 1998): the weighted least-squares linear fit
//     c = A_i^{-1} sum_j V_j W_ij p_ij f_j, A_i = sum_j V_j W_ij p_ij p_ij^T, p_ij = [1, x_j - x_i];
//     f_i = c_0 (= sum_j V_j f_j W^MLS_ij with W^MLS_ij = (A^{-1} e_1) . p_ij W_ij, the notes' beta form) and
//     the fit's slope grad f_i = c_{1..d} (the "diffuse" MLS derivative, Nayroles et al. 1992).
// Where a matrix is singular (too few neighbours: reciprocal condition number below 1e-8), CSPM falls back
// to the uncorrected antisymmetric gradient and MLS to Shepard with a zero slope.
#include <span>

#include "kernels/kernel_type.hpp"
#include "neighbors/neighbor_grid.hpp"
#include "physics/particle_view.hpp"
#include "physics/physics_params.hpp"

namespace varsph::physics::corrections {

struct Options {
  kernels::KernelType kernel = kernels::KernelType::Gaussian;
  double h = 1;
  double l = 9.47;     // paper_literal kernel constant
  bool walls = false;  // boundary particles take part (dynamic walls); else only fluid particles do

  template <int D>
  static Options of(const PhysicsParams<D>& p) {
    return {p.kernel, double(p.h), double(p.kernel_l), p.boundary == BoundaryModel::Dynamic};
  }
};

template <int D>
void shepard(const NeighborGrid<D>& grid, const ParticleView<D>& s, const Options& o, std::span<const Real> f,
             std::span<Real> out);

// out must not alias s.rho.
template <int D>
void shepard_density(const NeighborGrid<D>& grid, const ParticleView<D>& s, const Options& o, std::span<Real> out);

template <int D>
void cspm_gradient(const NeighborGrid<D>& grid, const ParticleView<D>& s, const Options& o, std::span<const Real> f,
                   std::span<Vec<D>> grad);

// grad: the CSPM gradient of f (from cspm_gradient).
template <int D>
void cspm_value(const NeighborGrid<D>& grid, const ParticleView<D>& s, const Options& o, std::span<const Real> f,
                std::span<const Vec<D>> grad, std::span<Real> out);

// grad may be empty (value only).
template <int D>
void mls(const NeighborGrid<D>& grid, const ParticleView<D>& s, const Options& o, std::span<const Real> f,
         std::span<Real> out, std::span<Vec<D>> grad = {});

}  // namespace varsph::physics::corrections
