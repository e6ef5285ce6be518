#pragma once
// Any kernel tabulated in s = r^2 / r_c^2 on [0, 1] (no exp or sqrt per pair): W and F (grad_i W =
// F x_ij) by linear interpolation between 4096 nodes. Relative interpolation error is below 1e-6
// for the shipped kernels (tests/kernels); `kernel.tabulated: false` evaluates them exactly.
#include <vector>

#include "kernels/kernel_eval.hpp"

namespace varsph::kernels {

// Linear interpolation in a table of kIntervals + 2 nodes over u = r^2 * scale (the one formula both
// the host class below and the device view use, so both give the same bits).
VARSPH_HD inline Real table_lerp(const Real* t, Real scale, Real r2, int intervals) {
  const Real u = r2 * scale;
  int k = int(u);
  if (k >= intervals) return Real(0);
  const Real a = u - Real(k);
  return t[k] + a * (t[k + 1] - t[k]);
}

// A Tabulated kernel seen through raw pointers (device memory in the CUDA backend, src/exec/): what a
// pass needs from a kernel, trivially copyable into a device launch.
template <int D>
struct TableView {
  Real support_, h_, scale_;
  const Real* w_;
  const Real* f_;
  int intervals_;
  VARSPH_HD Real support() const { return support_; }
  VARSPH_HD Real h() const { return h_; }
  VARSPH_HD Real w_r2(Real r2) const { return table_lerp(w_, scale_, r2, intervals_); }
  VARSPH_HD Real grad_factor_r2(Real r2) const { return table_lerp(f_, scale_, r2, intervals_); }
};

template <int D>
class Tabulated {
 public:
  static constexpr int kIntervals = 4096;

  Tabulated(KernelType type, double h, double l = 9.47) {
    const AnyKernel<D> exact(type, h, l);
    support_ = exact.support();
    h_ = Real(h);
    const double rc2 = double(support_) * double(support_);
    scale_ = Real(kIntervals / rc2);
    w_.resize(kIntervals + 2);
    f_.resize(kIntervals + 2);
    for (int k = 0; k <= kIntervals; ++k) {
      const double r = std::sqrt(rc2 * k / kIntervals);
      const auto s = exact(Real(std::min(r, double(support_) * (1 - 1e-12))));
      w_[k] = s.w;
      f_[k] = s.grad_factor;
    }
    w_[kIntervals + 1] = w_[kIntervals] = 0;  // compact support; the extra node guards k + 1
    f_[kIntervals + 1] = f_[kIntervals] = 0;
    // keep the node at r = 0 exact for F (the limit of dW/dr / r)
  }
  Real support() const { return support_; }
  Real h() const { return h_; }
  Real w_r2(Real r2) const { return table_lerp(w_.data(), scale_, r2, kIntervals); }
  Real grad_factor_r2(Real r2) const { return table_lerp(f_.data(), scale_, r2, kIntervals); }
  // The tables (kIntervals + 2 nodes each) and a view of them at other addresses (a device copy).
  const std::vector<Real>& w_values() const { return w_; }
  const std::vector<Real>& f_values() const { return f_; }
  TableView<D> view(const Real* w, const Real* f) const { return {support_, h_, scale_, w, f, kIntervals}; }
  // the F table and its scale, for the vectorised sweep (physics/simd/), which interpolates the same way
  const Real* f_table() const { return f_.data(); }
  Real table_scale() const { return scale_; }

 private:
  Real support_, h_, scale_;
  std::vector<Real> w_, f_;
};

}  // namespace varsph::kernels
