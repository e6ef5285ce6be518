#include "scene/parse_health.hpp"

namespace varsph::scene {

HealthSpec parse_health(JsonReader& r) {
  HealthSpec h;
  h.on_violation = r.choice("health.on_violation", "remove", {"remove", "stop"});
  h.max_density_error = r.number("health.max_density_error", 0.3, 1e-6, 100, "largest |rho/rho0 - 1|");
  h.max_mach = r.number("health.max_mach", 1.0, 1e-6, 1e6, "largest |v| / c0");
  h.max_removed_fraction = r.number("health.max_removed_fraction", 0.01, 0, 1,
                                    "fraction of the initial fluid particles removed within removal_window steps");
  h.removal_window = r.integer("health.removal_window", 20, 1, 1000000);
  h.max_removed_total = r.number("health.max_removed_total", 0.05, 0, 1,
                                 "fraction of the initial fluid particles removed over the run");
  h.max_energy_growth = r.number("health.max_energy_growth", 0.1, 0, 1e6,
                                 "largest rise of the total fluid energy over its initial value, in units of the "
                                 "energy scale (0 = off)");
  return h;
}

}  // namespace varsph::scene
