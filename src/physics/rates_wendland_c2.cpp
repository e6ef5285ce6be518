// The compiled passes for the wendland_c2 kernel (see rates_impl.hpp).
#include "kernels/wendland_c2.hpp"
#include "physics/rates_impl.hpp"

namespace varsph::physics {
template std::unique_ptr<Rates<2>> make_rates_with<2>(const PhysicsParams<2>&, kernels::WendlandC2<2>);
template std::unique_ptr<Rates<3>> make_rates_with<3>(const PhysicsParams<3>&, kernels::WendlandC2<3>);
}  // namespace varsph::physics
