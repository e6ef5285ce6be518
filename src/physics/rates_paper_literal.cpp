// The compiled passes for the paper_literal kernel (see rates_impl.hpp).
#include "kernels/paper_literal.hpp"
#include "physics/rates_impl.hpp"

namespace varsph::physics {
template std::unique_ptr<Rates<2>> make_rates_with<2>(const PhysicsParams<2>&, kernels::PaperLiteral<2>);
template std::unique_ptr<Rates<3>> make_rates_with<3>(const PhysicsParams<3>&, kernels::PaperLiteral<3>);
}  // namespace varsph::physics
