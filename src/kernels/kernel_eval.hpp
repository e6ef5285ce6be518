#pragma once
// Kernel evaluation by run-time type, for code outside the hot loops (probes, tests, tools). Returns
// W(r) and F(r) with grad_i W = F x_ij; both are zero at and beyond the support radius.
#include "kernels/cubic_spline.hpp"
#include "kernels/gaussian.hpp"
#include "kernels/kernel_type.hpp"
#include "kernels/paper_literal.hpp"
#include "kernels/wendland_c2.hpp"

namespace varsph::kernels {

struct KernelSample {
  Real w, grad_factor;
};

template <int D>
class AnyKernel {
 public:
  AnyKernel(KernelType type, double h, double l = 9.47) : type_(type), h_(h), l_(l) {}
  Real support() const { return visit([](const auto& k) { return k.support(); }); }
  KernelSample operator()(Real r) const {
    return visit([r](const auto& k) {
      if (r >= k.support()) return KernelSample{Real(0), Real(0)};
      return KernelSample{k.w_r2(r * r), k.grad_factor_r2(r * r)};
    });
  }

 private:
  template <class F>
  auto visit(F&& f) const {
    switch (type_) {
      case KernelType::CubicSpline: return f(CubicSpline<D>(h_));
      case KernelType::WendlandC2: return f(WendlandC2<D>(h_));
      case KernelType::PaperLiteral: return f(PaperLiteral<D>(h_, l_));
      case KernelType::Gaussian: break;
    }
    return f(Gaussian<D>(h_));
  }
  KernelType type_;
  double h_, l_;
};

}  // namespace varsph::kernels
