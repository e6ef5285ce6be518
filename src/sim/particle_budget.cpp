#include "sim/particle_budget.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/errors.hpp"

namespace varsph {
namespace {

std::string num(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", x);
  return b;
}

[[noreturn]] void refuse(const scene::Scene& s, const std::string& what) {
  throw InputError(s.file.string() + ": " + what + ", more than particles.max_count = " + num(max_particles(s)) +
                   "; expected a coarser particles.spacing, smaller bodies, or a higher particles.max_count");
}

}  // namespace

double max_particles(const scene::Scene& s) {
  static const auto key = nlohmann::json::json_pointer("/particles/max_count");
  return s.resolved.contains(key) && s.resolved.at(key).is_number() ? s.resolved.at(key).get<double>() : 1e7;
}

double estimate_body_particles(const scene::Scene& s, std::size_t index) {
  const scene::BodySpec& b = s.bodies[index];
  const int d = s.dimension;
  const double dx = s.spacing;
  if (b.shape == "points") return double(b.points.size());
  if (b.shape == "sphere")  // disc pi r^2 / dx^2, ball 4/3 pi r^3 / dx^3 (lattice points inside)
    return (d == 2 ? std::numbers::pi * std::pow(b.radius / dx, 2) : 4.0 / 3.0 * std::numbers::pi * std::pow(b.radius / dx, 3));
  if (b.shape != "box" && b.shape != "tank") return 0;
  // lattice cells per axis, as doubles (no overflow however absurd the size)
  double inner = 1, outer = 1, core = 1;
  for (int a = 0; a < d; ++a) {
    const double n = std::floor((b.max[std::size_t(a)] - b.min[std::size_t(a)]) / dx + 1e-6);
    inner *= n;
    if (b.shape == "tank") {
      const double closed = (b.open[2 * std::size_t(a)] ? 0 : 1) + (b.open[2 * std::size_t(a) + 1] ? 0 : 1);
      outer *= n + closed * b.layers;
    }
    core *= std::max(0.0, n - 2.0 * b.layers);
  }
  if (b.shape == "tank") return outer - inner;          // layers of cells outside the walls
  if (b.kind == "boundary") return inner - core;        // solid block: cells within `layers` of its surface
  return inner;                                          // fluid box: every cell
}

void check_particle_budget(const scene::Scene& s) {
  double total = 0;
  for (std::size_t k = 0; k < s.bodies.size(); ++k) {
    const double n = estimate_body_particles(s, k);
    total += n;
    if (!(total <= max_particles(s)))
      refuse(s, "bodies." + std::to_string(k) + " (" + s.bodies[k].shape + ") would produce about " + num(n) +
                    " particles at dx = " + num(s.spacing) + " m, " + num(total) + " with the bodies before it");
  }
}

void check_particle_count(const scene::Scene& s, std::size_t index, double count) {
  if (!(count <= max_particles(s)))
    refuse(s, "the bodies up to bodies." + std::to_string(index) + " produced " + num(count) + " particles");
}

}  // namespace varsph
