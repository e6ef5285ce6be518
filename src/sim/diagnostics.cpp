#include "sim/diagnostics.hpp"

#include <cmath>
#include <sstream>

#include "bodies/rigid_bodies.hpp"
#include "parallel/communicator.hpp"

namespace varsph {

double tait_internal_energy(double rho, double rho0, double B) {
  const double r = rho / rho0;
  const double r2 = r * r;
  return B / rho0 * (r2 * r2 * r2 / 6.0 + 1.0 / r - 7.0 / 6.0);
}

template <int D>
Diagnostics compute_diagnostics(const Simulation<D>& sim) {
  const auto& f = sim.fields();
  const auto& s = sim.scene();
  Diagnostics d;
  Vec<D> gmin;
  for (int a = 0; a < D; ++a) gmin[a] = Real(s.domain_min[a]);
  const double B = double(sim.eos().B);
  std::size_t n_fluid = 0;
  std::array<double, 3> L{};
  // serial sums in storage order: deterministic for any thread count
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.kind[i] != 0) continue;
    ++n_fluid;
    const double m = f.mass[i];
    const auto& v = f.v[i];
    const auto& x = f.x[i];
    for (int a = 0; a < D; ++a) d.momentum[a] += m * double(v[a]);
    if constexpr (D == 2) {
      L[2] += m * (double(x[0]) * double(v[1]) - double(x[1]) * double(v[0]));
    } else {
      L[0] += m * (double(x[1]) * double(v[2]) - double(x[2]) * double(v[1]));
      L[1] += m * (double(x[2]) * double(v[0]) - double(x[0]) * double(v[2]));
      L[2] += m * (double(x[0]) * double(v[1]) - double(x[1]) * double(v[0]));
    }
    const double v2 = double(v.squaredNorm());
    d.kinetic_energy += 0.5 * m * v2;
    d.potential_energy -= m * double(sim.params().gravity.dot(x - gmin));
    d.internal_energy += m * tait_internal_energy(f.rho[i], s.rho0, B);
    d.max_speed = std::max(d.max_speed, std::sqrt(v2));
    d.density_error_max = std::max(d.density_error_max, std::abs(double(f.rho[i]) / s.rho0 - 1.0));
  }
  if (sim.distributed()) {  // sums and maxima over every rank (sums to round-off, maxima exactly)
    double sums[10] = {d.momentum[0], d.momentum[1], d.momentum[2], L[0], L[1], L[2], d.kinetic_energy,
                       d.potential_energy, d.internal_energy, double(n_fluid)};
    double maxs[2] = {d.max_speed, d.density_error_max};
    sim.comm().sum(sums);
    sim.comm().max(maxs);
    for (int a = 0; a < 3; ++a) {
      d.momentum[a] = sums[a];
      L[a] = sums[3 + a];
    }
    d.kinetic_energy = sums[6];
    d.potential_energy = sums[7];
    d.internal_energy = sums[8];
    n_fluid = std::size_t(sums[9]);
    d.max_speed = maxs[0];
    d.density_error_max = maxs[1];
  }
  if (n_fluid > 0) {
    const double q2 = d.momentum[0] * d.momentum[0] + d.momentum[1] * d.momentum[1] + d.momentum[2] * d.momentum[2];
    d.momentum_Q = std::sqrt(q2) / double(n_fluid);
  }
  d.angular_momentum = D == 2 ? L[2] : std::sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]);
  if (const auto* rb = sim.rigid_bodies()) {  // every rank holds every body's state (RigidBodies::reduce_loads)
    const Eigen::Vector3d P = rb->momentum();
    for (int a = 0; a < 3; ++a) d.bodies_momentum[std::size_t(a)] = P[a];
    d.bodies_kinetic_energy = rb->kinetic_energy();
    Eigen::Vector3d g = Eigen::Vector3d::Zero(), x0 = Eigen::Vector3d::Zero();
    for (int a = 0; a < D; ++a) {
      g[a] = double(sim.params().gravity[a]);
      x0[a] = s.domain_min[std::size_t(a)];
    }
    double mass = 0;
    for (const auto& b : rb->bodies()) mass += b.mp.mass;
    d.bodies_potential_energy = rb->potential_energy(g) + mass * g.dot(x0);
  }
  return d;
}

template <int D>
std::string check_health(const Simulation<D>& sim) {
  const auto& f = sim.fields();
  const auto& s = sim.scene();
  // parallel scan for the first failing particle (lowest index: the same answer for any thread count)
  const long n = long(sim.size());
  long first_bad = n;
#pragma omp parallel for schedule(static) reduction(min : first_bad)
  for (long i = 0; i < n; ++i) {
    if (f.kind[i] != 0) continue;
    const auto& x = f.x[i];
    bool bad = !x.allFinite() || !f.v[i].allFinite() || !std::isfinite(double(f.rho[i]));
    for (int a = 0; a < D && !bad; ++a)
      bad = !s.periodic[a] && (double(x[a]) < s.domain_min[a] || double(x[a]) > s.domain_max[a]);
    bad = bad || std::abs(double(f.rho[i]) / s.rho0 - 1.0) > s.health.max_density_error;
    if (bad && i < first_bad) first_bad = i;
  }
  if (first_bad == n) return {};
  const std::size_t i = std::size_t(first_bad);
  const auto& x = f.x[i];
  std::ostringstream msg;
  if (!x.allFinite() || !f.v[i].allFinite() || !std::isfinite(double(f.rho[i]))) {
    msg << "particle id " << f.id[i] << " has a non-finite position, velocity or density";
    return msg.str();
  }
  for (int a = 0; a < D; ++a)
    if (!s.periodic[a] && (double(x[a]) < s.domain_min[a] || double(x[a]) > s.domain_max[a])) {
      msg << "particle id " << f.id[i] << " left the domain on axis " << a << " (coordinate " << double(x[a])
          << ", domain [" << s.domain_min[a] << ", " << s.domain_max[a] << "])";
      return msg.str();
    }
  const double err = std::abs(double(f.rho[i]) / s.rho0 - 1.0);
  msg << "particle id " << f.id[i] << " has density " << double(f.rho[i]) << " (|rho/rho0 - 1| = " << err
      << " > health.max_density_error = " << s.health.max_density_error << ")";
  return msg.str();
}

template Diagnostics compute_diagnostics<2>(const Simulation<2>&);
template Diagnostics compute_diagnostics<3>(const Simulation<3>&);
template std::string check_health<2>(const Simulation<2>&);
template std::string check_health<3>(const Simulation<3>&);

}  // namespace varsph
