#include "scene/sanity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/errors.hpp"

namespace varsph::scene {
namespace {

std::string num(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", x);
  return b;
}

struct Rules {
  const Scene& s;
  std::vector<std::string> warnings;

  [[noreturn]] void error(const std::string& key, const std::string& what) const {
    throw InputError(s.file.string() + ": key '" + key + "': " + what);
  }
  void warn(const std::string& key, const std::string& what) { warnings.push_back(key + ": " + what); }

  double norm(const std::vector<double>& v) const {
    double q = 0;
    for (double x : v) q += x * x;
    return std::sqrt(q);
  }

  // Fluid height and largest initial fluid speed, for the Mach rule (as the c0 "auto" rule sees them).
  void fluid_scales(double& height, double& speed) const {
    height = 0;
    speed = 0;
    const int d = s.dimension;
    for (const auto& b : s.bodies) {
      if (b.kind != "fluid") continue;
      if (!b.max.empty()) height = std::max(height, b.max[std::size_t(d - 1)] - b.min[std::size_t(d - 1)]);
      if (!b.center.empty()) height = std::max(height, 2 * b.radius);
      speed = std::max(speed, norm(b.velocity));
      for (const auto& v : b.velocities) speed = std::max(speed, norm(v));
    }
  }

  // Diagonal of the bounding box of the bodies whose extent is known without sampling (0 if a mesh).
  double bodies_diagonal() const {
    const std::size_t d = std::size_t(s.dimension);
    std::vector<double> lo(d, INFINITY), hi(d, -INFINITY);
    for (const auto& b : s.bodies) {
      if (b.shape == "mesh") return 0;
      for (std::size_t a = 0; a < d; ++a) {
        if (!b.min.empty()) { lo[a] = std::min(lo[a], b.min[a]); hi[a] = std::max(hi[a], b.max[a]); }
        if (!b.center.empty()) { lo[a] = std::min(lo[a], b.center[a] - b.radius); hi[a] = std::max(hi[a], b.center[a] + b.radius); }
        for (const auto& p : b.points) { lo[a] = std::min(lo[a], p[a]); hi[a] = std::max(hi[a], p[a]); }
      }
    }
    double q = 0;
    for (std::size_t a = 0; a < d; ++a)
      if (hi[a] >= lo[a]) q += (hi[a] - lo[a]) * (hi[a] - lo[a]);
    return std::sqrt(q);
  }

  void gravity() {
    using L = SanityLimits;
    const double g = norm(s.gravity);
    if (g > L::gravity_error)
      error("gravity", "|g| = " + num(g) + " m/s^2 is more than " + num(L::gravity_error) +
                           " m/s^2 (about 10^4 g, beyond any liquid experiment); expected m/s^2 (Earth: 9.81)");
    if (g > L::gravity_warning)
      warn("gravity", "|g| = " + num(g) + " m/s^2 is more than " + num(L::gravity_warning) +
                          " m/s^2 (about 10 g); Earth's is 9.81 m/s^2 - is this a centrifuge?");
  }

  void density() {
    using L = SanityLimits;
    if (s.rho0 < L::rho0_error_lo || s.rho0 > L::rho0_error_hi)
      error("fluid.rho0", "rho0 = " + num(s.rho0) + " kg/m^3 is outside [" + num(L::rho0_error_lo) + ", " +
                              num(L::rho0_error_hi) + "] (no fluid is that light or 40x denser than osmium); "
                              "expected kg/m^3 (water: 1000)");
    if (s.rho0 < L::rho0_warning_lo || s.rho0 > L::rho0_warning_hi)
      warn("fluid.rho0", "rho0 = " + num(s.rho0) + " kg/m^3 is outside [" + num(L::rho0_warning_lo) + ", " +
                             num(L::rho0_warning_hi) + "] (gases to liquid metals); water is 1000 kg/m^3");
  }

  void sound_speed() {
    using L = SanityLimits;
    if (s.c0 > L::c0_error)
      error("fluid.c0", "c0 = " + num(s.c0) + " m/s is faster than light; expected m/s (weakly-compressible SPH uses "
                            "about 10 x the largest flow speed)");
    if (s.c0 > L::c0_warning)
      warn("fluid.c0", "c0 = " + num(s.c0) + " m/s is above the sound speed of any liquid (water: 1480 m/s); "
                           "weakly-compressible SPH uses about 10 x the largest flow speed, and dt shrinks with 1/c0");
    double H_fluid, u0;
    fluid_scales(H_fluid, u0);
    const double g = norm(s.gravity);
    // the flow speed: the scene's named reference speed (a still tank, a slow body), else the dam-break speed
    // sqrt(2 g H) of the reference height or the fluid bodies' height; never below the initial velocities
    const double H = s.reference_height >= 0 ? s.reference_height : H_fluid;
    const bool named_u = s.reference_speed >= 0;
    const double u = std::max(named_u ? s.reference_speed : std::sqrt(2 * g * H), u0);
    if (u > 0 && u > L::mach_warning * s.c0 * (1 + 1e-9))  // the auto rule's 10x sits exactly on the line
      warn("fluid.c0", "c0 = " + num(s.c0) + " m/s is less than 10 x the expected flow speed " + num(u) + " m/s (" +
                           (named_u ? "max of fluid.reference_speed" : "max of sqrt(2 g H)") +
                           " and the initial velocities): Mach " + num(u / s.c0) +
                           ", density errors above 1 % (Monaghan 1994 asks for Mach <= 0.1)");
    // with a named speed the Mach rule no longer sees the column's weight: the hydrostatic compression
    // g H / c0^2 of the Tait equation's linear part (seed paper eq. (11)) is checked on its own
    const double squeeze = g * H_fluid / (s.c0 * s.c0);
    if (named_u && squeeze > L::hydrostatic_warning)
      warn("fluid.c0", "c0 = " + num(s.c0) + " m/s compresses the fluid's " + num(H_fluid) +
                           " m column by g H / c0^2 = " + num(100 * squeeze) + " % at its bottom (more than " +
                           num(100 * L::hydrostatic_warning) + " %)");
  }

  void domain() {
    using L = SanityLimits;
    double diag = 0;
    for (std::size_t a = 0; a < s.domain_min.size(); ++a) {
      const double ext = s.domain_max[a] - s.domain_min[a];
      diag += ext * ext;
      const double far = std::max(std::abs(s.domain_min[a]), std::abs(s.domain_max[a]));
      if (ext / s.spacing > L::domain_cells_error || far / s.spacing > L::domain_cells_error)
        error("domain.max", "the domain reaches " + num(far) + " m on axis " + std::to_string(a) + ", " +
                                num(std::max(ext, far) / s.spacing) + " spacings (dx = " + num(s.spacing) +
                                " m), more than " + num(L::domain_cells_error) +
                                "; no grid covers it and positions there cannot resolve dx - expected metres");
    }
    diag = std::sqrt(diag);
    const double bodies = bodies_diagonal();
    if (bodies > 0 && diag > L::domain_empty_warning * bodies)
      warn("domain", "the domain's diagonal " + num(diag) + " m is more than " + num(L::domain_empty_warning) +
                         " x that of the bodies (" + num(bodies) + " m); most of it stays empty (units?)");
  }

  void time_step() {
    using L = SanityLimits;
    if (s.dt) {
      const double courant = s.c0 * *s.dt / s.h;  // acoustic CFL number
      if (courant > L::courant_error)
        error("integrator.dt", "dt = " + num(*s.dt) + " s is " + num(courant) + " x the acoustic limit h/c0 = " +
                                   num(s.h / s.c0) + " s, more than " + num(L::courant_error) +
                                   " x; no scheme is stable there (explicit: c0 dt/h < ~0.4; variational: eq. 54)");
      if (courant > L::courant_warning)
        warn("integrator.dt", "dt = " + num(*s.dt) + " s is " + num(courant) + " x the acoustic limit h/c0 = " +
                                  num(s.h / s.c0) + " s; explicit schemes need c0 dt/h below about 0.4 "
                                  "(integrator.cfl 0.2 chooses dt for you)");
      const double g = norm(s.gravity);
      if (g > 0 && *s.dt > std::sqrt(s.h / g))
        warn("integrator.dt", "dt = " + num(*s.dt) + " s is above the force limit sqrt(h/|g|) = " +
                                  num(std::sqrt(s.h / g)) + " s");
    }
    const double dt = s.dt ? *s.dt : s.cfl_acoustic * s.h / s.c0;  // the acoustic limit bounds dt from above
    const double steps = s.t_end / dt;
    const std::string est = s.dt ? "" : " (at most " + num(dt) + " s each from the acoustic CFL limit)";
    if (steps > L::steps_error)
      error("time.end", "time.end = " + num(s.t_end) + " s needs " + num(steps) + " steps" + est + ", more than " +
                            num(L::steps_error) + "; no run finishes that - expected seconds");
    if (steps > L::steps_warning)
      warn("time.end", "time.end = " + num(s.t_end) + " s needs " + num(steps) + " steps" + est);
    const double frames = s.t_end / s.output_every;
    if (frames > L::frames_error)
      error("output.every", "output.every = " + num(s.output_every) + " s writes " + num(frames) +
                                " frames up to time.end, more than " + num(L::frames_error) + " files");
    if (frames > L::frames_warning)
      warn("output.every", "output.every = " + num(s.output_every) + " s writes " + num(frames) + " frames");
  }

  // A box holds floor(extent / dx) particles across (sim/build_particles.cpp cells_in): an extent a hair under a
  // whole number of spacings (a length written with few digits) loses a whole layer and leaves a gap of nearly
  // one spacing at its max side, a hole in a wall of `layers` particles that fluid can fall through.
  void box_extents() {
    using L = SanityLimits;
    const double dx = s.spacing;
    if (!(dx > 0)) return;
    for (std::size_t i = 0; i < s.bodies.size(); ++i) {
      const auto& b = s.bodies[i];
      if ((b.shape != "box" && b.shape != "tank") || b.min.size() != b.max.size()) continue;
      for (std::size_t a = 0; a < b.min.size(); ++a) {
        const double q = (b.max[a] - b.min[a]) / dx;
        const double n = std::floor(q + 1e-6);  // the sampler's count
        if (n >= 1 && q - n > L::box_extent_shortfall)
          warn("bodies." + std::to_string(i) + ".max", "the " + b.shape + " is " + num(q) + " spacings long on axis " +
                   std::to_string(a) + ": it holds " + num(n) + " particles across and leaves a gap of " + num(q - n) +
                   " spacings at its max side; " + num(n + 1) + " spacings (min = " + num(b.max[a] - (n + 1) * dx) +
                   " or max = " + num(b.min[a] + (n + 1) * dx) + ") was likely meant: write lengths with more digits");
      }
    }
  }
};

}  // namespace

std::vector<std::string> check_sanity(const Scene& s) {
  Rules r{s, {}};
  r.gravity();
  r.density();
  r.sound_speed();
  r.domain();
  r.time_step();
  r.box_extents();
  return std::move(r.warnings);
}

}  // namespace varsph::scene
