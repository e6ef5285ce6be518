#pragma once
// How mDBC sets a boundary particle from its ghost node (physics/wall_mdbc.hpp).
namespace varsph::physics {
enum class MdbcExtrapolation {
  Gradient,     // rho_b = rho_g + (x_b - x_g) . grad rho_g (English et al. 2022)
  Hydrostatic,  // p_b = p_g + rho0 (g - a_w) . (x_b - x_g) (DualSPHysics 5.4 pressure cloning)
};
}  // namespace varsph::physics
