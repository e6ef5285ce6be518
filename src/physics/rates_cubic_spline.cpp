// The compiled passes for the cubic_spline kernel (see rates_impl.hpp).
#include "kernels/cubic_spline.hpp"
#include "physics/rates_impl.hpp"

namespace varsph::physics {
template std::unique_ptr<Rates<2>> make_rates_with<2>(const PhysicsParams<2>&, kernels::CubicSpline<2>);
template std::unique_ptr<Rates<3>> make_rates_with<3>(const PhysicsParams<3>&, kernels::CubicSpline<3>);
}  // namespace varsph::physics
