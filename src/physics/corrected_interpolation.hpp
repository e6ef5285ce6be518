#pragma once
// First-order consistent SPH interpolation of a fluid field f at an arbitrary point x_g (kernel and
// kernel-gradient corrected, Liu & Liu 2006, "Restoring particle consistency in SPH", Appl. Numer. Math.
// 56:19-36): with x_jg = x_j - x_g, V_j = m_j / rho_j, u_j = (W_gj, s grad_g W_gj), e_j = (1, x_jg / s),
//   (sum_j V_j u_j e_j^T) [f_g ; s grad f_g] = sum_j V_j f_j u_j,
// exact for linear fields even where the support is cut by a wall or a free surface. s is the kernel
// support (so the matrix is dimensionless and ~ identity in the bulk). Where the node is nearly dry or
// the matrix ill conditioned (DualSPHysics' mDBC limits: |det| >= 1e-3, condition number <= 50, kernel
// sum >= 0.1) the zeroth-order Shepard value sum V_j f_j W / sum V_j W is returned. Used by the mDBC
// ghost nodes (physics/wall_mdbc.hpp) and the pressure sensors (sim/probes.cpp).
#include <cmath>

#include <Eigen/Dense>

#include "core/real.hpp"

namespace varsph::physics {

template <int D>
class CorrectedInterpolation {
 public:
  explicit CorrectedInterpolation(double support) : inv_s_(1.0 / support) {}

  // One fluid neighbour j: x_gj = x_g - x_j, kernel value w and gradient factor F (grad_g W = F x_gj),
  // volume V_j and the field value f_j.
  void add(const Vec<D>& x_gj, double w, double F, double V, double f) {
    Eigen::Matrix<double, D + 1, 1> u, e;
    u[0] = w;
    e[0] = 1;
    for (int a = 0; a < D; ++a) {
      u[a + 1] = F * double(x_gj[a]) / inv_s_;  // s grad W
      e[a + 1] = -double(x_gj[a]) * inv_s_;     // (x_j - x_g) / s
    }
    A_.noalias() += (V * u) * e.transpose();
    b_ += (V * f) * u;
    ++count_;
  }

  struct Result {
    double value = 0;                                                     // f at x_g
    Eigen::Matrix<double, D, 1> gradient = Eigen::Matrix<double, D, 1>::Zero();  // grad f at x_g
    double kernel_sum = 0;  // sum V_j W_gj (about 1 when the support is full of fluid)
    bool first_order = false;
    bool empty = true;      // no fluid neighbour at all
  };

  Result solve() const {
    Result r;
    r.kernel_sum = A_(0, 0);
    if (count_ == 0 || !(r.kernel_sum > 0)) return r;
    r.empty = false;
    r.value = b_[0] / r.kernel_sum;  // Shepard
    if (r.kernel_sum < kSubmerged) return r;
    const double det = A_.determinant();
    if (!(std::abs(det) >= kDetMin)) return r;
    const Matrix inv = A_.inverse();
    const double cond = A_.cwiseAbs().rowwise().sum().maxCoeff() * inv.cwiseAbs().rowwise().sum().maxCoeff();
    if (!(cond <= kCondMax)) return r;
    const Eigen::Matrix<double, D + 1, 1> sol = inv * b_;
    r.value = sol[0];
    r.gradient = sol.template tail<D>() * inv_s_;
    r.first_order = true;
    return r;
  }

  static constexpr double kDetMin = 1e-3;
  static constexpr double kCondMax = 50.0;
  static constexpr double kSubmerged = 0.1;

 private:
  using Matrix = Eigen::Matrix<double, D + 1, D + 1>;
  double inv_s_;
  Matrix A_ = Matrix::Zero();
  Eigen::Matrix<double, D + 1, 1> b_ = Eigen::Matrix<double, D + 1, 1>::Zero();
  int count_ = 0;
};

}  // namespace varsph::physics
