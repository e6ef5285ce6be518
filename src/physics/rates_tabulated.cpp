// The compiled passes for tabulated kernels (kernels/tabulated.hpp: any kernel type; the default).
#include "kernels/tabulated.hpp"
#include "physics/rates_impl.hpp"

namespace varsph::physics {
template std::unique_ptr<Rates<2>> make_rates_with<2>(const PhysicsParams<2>&, kernels::Tabulated<2>);
template std::unique_ptr<Rates<3>> make_rates_with<3>(const PhysicsParams<3>&, kernels::Tabulated<3>);
}  // namespace varsph::physics
