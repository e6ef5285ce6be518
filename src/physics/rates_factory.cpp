// Resolves the scene's kernel into one compiled Rates implementation (rates_impl.hpp); each kernel's
// passes are compiled in their own translation unit (rates_<kernel>.cpp) so builds run in parallel.
#include "kernels/cubic_spline.hpp"
#include "kernels/gaussian.hpp"
#include "kernels/paper_literal.hpp"
#include "kernels/tabulated.hpp"
#include "kernels/wendland_c2.hpp"
#include "physics/rates.hpp"

namespace varsph::physics {

template <int D, class Kernel>
std::unique_ptr<Rates<D>> make_rates_with(const PhysicsParams<D>& p, Kernel k);

template <int D>
std::unique_ptr<Rates<D>> make_rates(const PhysicsParams<D>& p) {
  using kernels::KernelType;
  if (p.kernel_tabulated) return make_rates_with<D>(p, kernels::Tabulated<D>(p.kernel, p.h, p.kernel_l));
  switch (p.kernel) {
    case KernelType::Gaussian: return make_rates_with<D>(p, kernels::Gaussian<D>(p.h));
    case KernelType::CubicSpline: return make_rates_with<D>(p, kernels::CubicSpline<D>(p.h));
    case KernelType::WendlandC2: return make_rates_with<D>(p, kernels::WendlandC2<D>(p.h));
    case KernelType::PaperLiteral: return make_rates_with<D>(p, kernels::PaperLiteral<D>(p.h, p.kernel_l));
  }
  return nullptr;
}

template std::unique_ptr<Rates<2>> make_rates<2>(const PhysicsParams<2>&);
template std::unique_ptr<Rates<3>> make_rates<3>(const PhysicsParams<3>&);

}  // namespace varsph::physics
