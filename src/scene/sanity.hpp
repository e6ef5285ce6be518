#pragma once
// Sanity rules for physics inputs that are finite and in range for the parser but absurd (docs/scene.md,
// "Sanity checks"): a value that cannot be meant is an InputError (exit 2) naming the file, the key, the
// rule and the value; a merely unusual one is a warning (returned; `varsph info` lists them, `run` and
// `sample` print them on stderr).
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace varsph::scene {

// The rules' thresholds (also quoted in docs/scene.md and the messages).
struct SanityLimits {
  static constexpr double gravity_error = 1e5;      // |g| [m/s^2], about 10^4 g: no liquid experiment
  static constexpr double gravity_warning = 100;    // |g| [m/s^2], about 10 g
  static constexpr double rho0_error_lo = 1e-3, rho0_error_hi = 1e6;       // [kg/m^3]
  static constexpr double rho0_warning_lo = 0.5, rho0_warning_hi = 3e4;    // [kg/m^3]
  static constexpr double c0_error = 299792458;     // [m/s], the speed of light
  static constexpr double c0_warning = 1e4;         // [m/s], above the sound speed of any liquid
  static constexpr double mach_warning = 0.1;       // flow speed / c0 above this: density error > 1 %
  static constexpr double hydrostatic_warning = 0.01;  // g H / c0^2 above this: the column squeezed by > 1 %
  static constexpr double box_extent_shortfall = 0.99;  // a box this far past a whole number of spacings: a rounded length
  static constexpr double domain_cells_error = 1e9;  // domain extent / dx on one axis
  static constexpr double domain_empty_warning = 100;  // domain diagonal / bodies' diagonal
  static constexpr double courant_error = 100;      // c0 dt / h
  static constexpr double courant_warning = 1;      // c0 dt / h
  static constexpr double steps_error = 1e10, steps_warning = 1e8;  // time.end / dt
  static constexpr double frames_error = 1e7, frames_warning = 1e5;  // time.end / output.every
};

// Applies the rules to a parsed scene; throws InputError for a value that cannot be meant, returns the
// warnings ("KEY: why; what is usual") for unusual ones. parse_scene() calls it (so every scene that
// parses has passed the error rules); `varsph info`, `run` and `sample` call it again for the warnings.
std::vector<std::string> check_sanity(const Scene& s);

}  // namespace varsph::scene
