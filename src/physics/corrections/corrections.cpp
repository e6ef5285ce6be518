#include "physics/corrections/corrections.hpp"

#include <Eigen/LU>

#include "kernels/cubic_spline.hpp"
#include "kernels/gaussian.hpp"
#include "kernels/paper_literal.hpp"
#include "kernels/wendland_c2.hpp"
#include "physics/pair_loop.hpp"

namespace varsph::physics::corrections {
namespace {

constexpr Real kMinRcond = Real(1e-8);

// The kernel is chosen once per call (one switch), the pair loop is compiled for it.
template <int D, class F>
void with_kernel(const Options& o, F&& f) {
  using kernels::KernelType;
  switch (o.kernel) {
    case KernelType::CubicSpline: return f(kernels::CubicSpline<D>(o.h));
    case KernelType::WendlandC2: return f(kernels::WendlandC2<D>(o.h));
    case KernelType::PaperLiteral: return f(kernels::PaperLiteral<D>(o.h, o.l));
    case KernelType::Gaussian: break;
  }
  f(kernels::Gaussian<D>(o.h));
}

template <int D>
struct Participation {
  const ParticleView<D>& s;
  bool walls;
  bool operator()(std::size_t i) const { return walls || s.kind[i] == 0; }
  Real volume(std::size_t i) const { return s.mass[i] / s.rho[i]; }
};

// Shepard 1968: num = sum V_j f_j W, den = sum V_j W. `density`: num = sum m_j W (Colagrossi & Landrini 2003).
template <int D, class Kernel, bool Density>
struct ShepardPass {
  const Kernel& W;
  Participation<D> in;
  std::span<const Real> f;
  std::span<Real> out;
  struct Acc {
    Real num, den;
  };
  bool active(std::size_t i) const { return in(i); }
  Acc begin(std::size_t i) const {
    const Real w0 = W.w_r2(Real(0)), V = in.volume(i);
    return {(Density ? in.s.mass[i] : V * f[i]) * w0, V * w0};
  }
  void pair(Acc& a, std::size_t, std::size_t j, const Vec<D>&, Real r2) const {
    if (!in(j)) return;
    const Real w = W.w_r2(r2), V = in.volume(j);
    a.num += (Density ? in.s.mass[j] : V * f[j]) * w;
    a.den += V * w;
  }
  void end(std::size_t i, const Acc& a) const { out[i] = a.num / a.den; }
};

template <int D, class Kernel>
struct CspmGradientPass {
  using Mat = Eigen::Matrix<Real, D, D>;
  const Kernel& W;
  Participation<D> in;
  std::span<const Real> f;
  std::span<Vec<D>> grad;
  struct Acc {
    Mat M;
    Vec<D> s;
  };
  bool active(std::size_t i) const { return in(i); }
  Acc begin(std::size_t) const { return {Mat::Zero(), Vec<D>::Zero()}; }
  void pair(Acc& a, std::size_t i, std::size_t j, const Vec<D>& xij, Real r2) const {
    if (!in(j)) return;
    const Vec<D> g = W.grad_factor_r2(r2) * xij;  // grad_i W_ij
    const Real V = in.volume(j);
    a.M -= V * xij * g.transpose();  // (x_j - x_i) (grad_i W_ij)^T, Chen et al. 1999
    a.s += V * (f[j] - f[i]) * g;
  }
  void end(std::size_t i, const Acc& a) const {
    // s^b = sum_a df/dx^a M^{ab}  =>  grad f = M^{-T} s
    const Eigen::PartialPivLU<Mat> lu(a.M.transpose());
    grad[i] = lu.rcond() > kMinRcond ? Vec<D>(lu.solve(a.s)) : a.s;
  }
};

template <int D, class Kernel>
struct CspmValuePass {
  const Kernel& W;
  Participation<D> in;
  std::span<const Real> f;
  std::span<const Vec<D>> grad;
  std::span<Real> out;
  struct Acc {
    Real num, den;
    Vec<D> moment;  // sum_j V_j (x_j - x_i) W_ij
  };
  bool active(std::size_t i) const { return in(i); }
  Acc begin(std::size_t i) const {
    const Real w0 = W.w_r2(Real(0)), V = in.volume(i);
    return {V * f[i] * w0, V * w0, Vec<D>::Zero()};
  }
  void pair(Acc& a, std::size_t, std::size_t j, const Vec<D>& xij, Real r2) const {
    if (!in(j)) return;
    const Real w = W.w_r2(r2) * in.volume(j);
    a.num += f[j] * w;
    a.den += w;
    a.moment -= w * xij;
  }
  void end(std::size_t i, const Acc& a) const { out[i] = (a.num - grad[i].dot(a.moment)) / a.den; }
};

template <int D, class Kernel>
struct MlsPass {
  static constexpr int N = D + 1;
  using Mat = Eigen::Matrix<Real, N, N>;
  using Col = Eigen::Matrix<Real, N, 1>;
  const Kernel& W;
  Participation<D> in;
  std::span<const Real> f;
  std::span<Real> out;
  std::span<Vec<D>> grad;
  struct Acc {
    Mat A;
    Col b;
  };
  bool active(std::size_t i) const { return in(i); }
  Acc begin(std::size_t i) const {
    const Real w = W.w_r2(Real(0)) * in.volume(i);
    Acc a{Mat::Zero(), Col::Zero()};
    a.A(0, 0) = w;  // p_ii = [1, 0]
    a.b(0) = w * f[i];
    return a;
  }
  void pair(Acc& a, std::size_t, std::size_t j, const Vec<D>& xij, Real r2) const {
    if (!in(j)) return;
    const Real w = W.w_r2(r2) * in.volume(j);
    Col p;
    p(0) = 1;
    p.template tail<D>() = -xij;  // x_j - x_i
    a.A.noalias() += (w * p) * p.transpose();  // Dilts 1999
    a.b += (w * f[j]) * p;
  }
  void end(std::size_t i, const Acc& a) const {
    const Eigen::PartialPivLU<Mat> lu(a.A);
    if (lu.rcond() > kMinRcond) {
      const Col c = lu.solve(a.b);
      out[i] = c(0);
      if (!grad.empty()) grad[i] = c.template tail<D>();
    } else {
      out[i] = a.b(0) / a.A(0, 0);  // Shepard
      if (!grad.empty()) grad[i] = Vec<D>::Zero();
    }
  }
};

}  // namespace

template <int D>
void shepard(const NeighborGrid<D>& grid, const ParticleView<D>& s, const Options& o, std::span<const Real> f,
             std::span<Real> out) {
  with_kernel<D>(o, [&](const auto& W) {
    ShepardPass<D, std::decay_t<decltype(W)>, false> pass{W, {s, o.walls}, f, out};
    for_each_particle_pairs<D>(grid, s.x, W.support(), pass);
  });
}

template <int D>
void shepard_density(const NeighborGrid<D>& grid, const ParticleView<D>& s, const Options& o, std::span<Real> out) {
  with_kernel<D>(o, [&](const auto& W) {
    ShepardPass<D, std::decay_t<decltype(W)>, true> pass{W, {s, o.walls}, {}, out};
    for_each_particle_pairs<D>(grid, s.x, W.support(), pass);
  });
}

template <int D>
void cspm_gradient(const NeighborGrid<D>& grid, const ParticleView<D>& s, const Options& o, std::span<const Real> f,
                   std::span<Vec<D>> grad) {
  with_kernel<D>(o, [&](const auto& W) {
    CspmGradientPass<D, std::decay_t<decltype(W)>> pass{W, {s, o.walls}, f, grad};
    for_each_particle_pairs<D>(grid, s.x, W.support(), pass);
  });
}

template <int D>
void cspm_value(const NeighborGrid<D>& grid, const ParticleView<D>& s, const Options& o, std::span<const Real> f,
                std::span<const Vec<D>> grad, std::span<Real> out) {
  with_kernel<D>(o, [&](const auto& W) {
    CspmValuePass<D, std::decay_t<decltype(W)>> pass{W, {s, o.walls}, f, grad, out};
    for_each_particle_pairs<D>(grid, s.x, W.support(), pass);
  });
}

template <int D>
void mls(const NeighborGrid<D>& grid, const ParticleView<D>& s, const Options& o, std::span<const Real> f,
         std::span<Real> out, std::span<Vec<D>> grad) {
  with_kernel<D>(o, [&](const auto& W) {
    MlsPass<D, std::decay_t<decltype(W)>> pass{W, {s, o.walls}, f, out, grad};
    for_each_particle_pairs<D>(grid, s.x, W.support(), pass);
  });
}

#define VARSPH_CORRECTIONS(D)                                                                                   \
  template void shepard<D>(const NeighborGrid<D>&, const ParticleView<D>&, const Options&,                       \
                           std::span<const Real>, std::span<Real>);                                              \
  template void shepard_density<D>(const NeighborGrid<D>&, const ParticleView<D>&, const Options&,               \
                                   std::span<Real>);                                                             \
  template void cspm_gradient<D>(const NeighborGrid<D>&, const ParticleView<D>&, const Options&,                 \
                                 std::span<const Real>, std::span<Vec<D>>);                                      \
  template void cspm_value<D>(const NeighborGrid<D>&, const ParticleView<D>&, const Options&,                    \
                              std::span<const Real>, std::span<const Vec<D>>, std::span<Real>);                  \
  template void mls<D>(const NeighborGrid<D>&, const ParticleView<D>&, const Options&, std::span<const Real>,    \
                       std::span<Real>, std::span<Vec<D>>);
VARSPH_CORRECTIONS(2)
VARSPH_CORRECTIONS(3)
#undef VARSPH_CORRECTIONS

}  // namespace varsph::physics::corrections
