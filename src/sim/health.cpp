#include "sim/health.hpp"

#include "core/team.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <type_traits>

#include "parallel/collective.hpp"
#include "sim/diagnostics.hpp"

namespace varsph {
namespace {

constexpr std::size_t kBlock = 2048;  // fixed summation blocks: sums do not depend on the thread count

std::string fmt(double v) {
  std::ostringstream o;
  o.precision(6);
  o << v;
  return o.str();
}

}  // namespace

const char* removal_rule_name(RemovalRule r) {
  switch (r) {
    case RemovalRule::Domain: return "domain";
    case RemovalRule::Density: return "density";
    case RemovalRule::Speed: return "speed";
  }
  return "?";
}

template <int D>
HealthMonitor<D>::HealthMonitor(const scene::Scene& s)
    : spec_(s.health), rho0_(s.rho0), c0_(s.c0), dmin_(s.domain_min), dmax_(s.domain_max), periodic_(s.periodic) {
  stop_ = spec_.on_violation == "stop";
  bool moving = false;
  for (const auto& b : s.bodies) moving |= !b.motion.is_null() || b.kind == "rigid";
  bool body_force = false;
  for (double f : s.body_force) body_force |= f != 0.0;
  // inlets and outlets carry energy in and out: no closed-system energy bound
  energy_on_ = spec_.max_energy_growth > 0 && !moving && !body_force && s.open_boundaries.empty();
  window_.assign(std::size_t(spec_.removal_window), 0);
}

namespace {

// A distributed run's energies summed over ranks (to round-off: the order of the ranks' sums differs
// from one process's block order; the rules compare them with thresholds, not bits).
template <int D>
void sum_over_ranks(const Simulation<D>& sim, FluidEnergy& e) {
  double v[4] = {e.kinetic, e.potential, e.internal, e.mass};
  sim.comm().sum(std::span<double>(v, 4));
  e = {v[0], v[1], v[2], v[3]};
}

}  // namespace

template <int D>
FluidEnergy HealthMonitor<D>::fluid_energy(const Simulation<D>& sim, const std::uint8_t* skip) const {
  const auto& f = sim.fields();
  const auto& s = sim.scene();
  Vec<D> gmin;
  for (int a = 0; a < D; ++a) gmin[a] = Real(s.domain_min[a]);
  const Vec<D> g = sim.params().gravity;
  const double B = double(sim.eos().B);
  const std::size_t n = sim.size();
  const long nb = long((n + kBlock - 1) / kBlock);
  auto& part = energy_part_;
  part.resize(std::size_t(nb));  // grows once
#pragma omp parallel for schedule(static)
  for (long b = 0; b < nb; ++b) {
    FluidEnergy e;
    const std::size_t end = std::min(n, std::size_t(b + 1) * kBlock);
    for (std::size_t i = std::size_t(b) * kBlock; i < end; ++i) {
      if (f.kind[i] != 0 || (skip && skip[i])) continue;
      const double m = f.mass[i];
      e.kinetic += 0.5 * m * double(f.v[i].squaredNorm());
      e.potential -= m * double(g.dot(f.x[i] - gmin));
      e.internal += m * tait_internal_energy(f.rho[i], s.rho0, B);  // seed eq. (16)-(17)
      e.mass += m;
    }
    part[std::size_t(b)] = e;
  }
  FluidEnergy sum;
  for (long b = 0; b < nb; ++b) {
    const FluidEnergy& e = part[std::size_t(b)];
    sum.kinetic += e.kinetic;
    sum.potential += e.potential;
    sum.internal += e.internal;
    sum.mass += e.mass;
  }
  if (sim.distributed()) sum_over_ranks(sim, sum);
  return sum;
}

template <int D>
void HealthMonitor<D>::start(const Simulation<D>& sim) {
  n0_ = sim.count(0);
  const FluidEnergy e = fluid_energy(sim);
  e0_ = e.total();
  const double u = 0.1 * c0_;  // the design speed of the c0 = 10 U rule
  e_scale_ = e.kinetic + std::abs(e.potential) + e.internal + 0.5 * e.mass * u * u;
  started_ = true;
}

template <int D>
std::string HealthMonitor<D>::violation_message(const Simulation<D>& sim, std::size_t i, RemovalRule r) const {
  const auto& f = sim.fields();
  std::ostringstream msg;
  msg << "particle id " << f.id[i];
  if (r == RemovalRule::Domain) {
    for (int a = 0; a < D; ++a) {
      const double xa = double(f.x[i][a]);
      if (!periodic_[std::size_t(a)] && (xa < dmin_[std::size_t(a)] || xa > dmax_[std::size_t(a)])) {
        msg << " left the domain on axis " << a << " (coordinate " << xa << ", domain [" << dmin_[std::size_t(a)]
            << ", " << dmax_[std::size_t(a)] << "])";
        break;
      }
    }
  } else if (r == RemovalRule::Density) {
    const double err = std::abs(double(f.rho[i]) / rho0_ - 1.0);
    msg << " has density " << double(f.rho[i]) << " (|rho/rho0 - 1| = " << err
        << " > health.max_density_error = " << spec_.max_density_error << ")";
  } else {
    msg << " has speed " << double(f.v[i].norm()) << " m/s (> health.max_mach x c0 = " << spec_.max_mach * c0_
        << " m/s)";
  }
  return msg.str();
}

template <int D>
void HealthMonitor<D>::record(const Simulation<D>& sim, std::size_t i, RemovalRule r) {
  const auto& f = sim.fields();
  RemovedParticle p;
  p.step = sim.step();
  p.time = sim.time();
  p.id = f.id[i];
  p.rule = r;
  for (int a = 0; a < D; ++a) {
    p.x[std::size_t(a)] = double(f.x[i][a]);
    p.v[std::size_t(a)] = double(f.v[i][a]);
  }
  p.rho = double(f.rho[i]);
  p.p = double(f.p[i]);
  // its neighbourhood when removed (a splash particle has few), from the grid built for this state
  const auto& g = sim.grid();
  const auto& blocks = g.blocks();
  const auto it = std::upper_bound(blocks.begin(), blocks.end(), std::uint32_t(i),
                                   [](std::uint32_t v, const CellBlock& b) { return v < b.begin; });
  if (it != blocks.begin()) {
    const CellBlock& b = *(it - 1);
    if (i >= b.begin && i < b.end) {
      const Real r2 = sim.rates().support() * sim.rates().support();
      for (std::uint32_t k = b.nbr_begin; k < b.nbr_end; ++k) {
        const NeighborRange& nr = g.ranges()[k];
        const Vec<D>& sh = g.shift(nr.shift);
        for (std::uint32_t j = nr.begin; j < nr.end; ++j) {
          if (j == i || (f.x[j] + sh - f.x[i]).squaredNorm() >= r2) continue;
          (f.kind[j] == 0 ? p.fluid_neighbours : p.boundary_neighbours) += 1;
        }
      }
    }
  }
  last_removed_.push_back(p);
}

template <int D>
void HealthMonitor<D>::flag_pass(const Simulation<D>& sim) {
  const auto& f = sim.fields();
  const std::size_t n = sim.size();
  const long nb = long((n + kBlock - 1) / kBlock);
  team_single([&] {
    if (flag_.size() < n) flag_.resize(n);  // grows once; particles are only ever removed
    block_part_.resize(std::size_t(nb));    // idem
  });
  std::uint8_t* flag = flag_.data();
  BlockFlags* part = block_part_.data();
  const double rho_lo = rho0_ * (1.0 - spec_.max_density_error), rho_hi = rho0_ * (1.0 + spec_.max_density_error);
  const double v2_max = (spec_.max_mach * c0_) * (spec_.max_mach * c0_);
  // domain bounds per axis; periodic axes never flag
  std::array<double, D> lo, hi;
  for (int a = 0; a < D; ++a) {
    const bool per = periodic_[std::size_t(a)];
    lo[std::size_t(a)] = per ? -HUGE_VAL : dmin_[std::size_t(a)];
    hi[std::size_t(a)] = per ? HUGE_VAL : dmax_[std::size_t(a)];
  }
  // one pass: flags, and the energy of the fluid that stays (seed eq. 16-17 for the internal part)
  Vec<D> gmin;
  for (int a = 0; a < D; ++a) gmin[a] = Real(dmin_[std::size_t(a)]);
  const Vec<D> g = sim.params().gravity;
  const double B = double(sim.eos().B);
  const bool energy = energy_on_;
  team_for(nb, [&](long b) {
    BlockFlags s;
    const std::size_t end = std::min(n, std::size_t(b + 1) * kBlock);
    for (std::size_t i = std::size_t(b) * kBlock; i < end; ++i) {
      std::uint8_t fl = 0;
      const auto& x = f.x[i];
      const double rho = double(f.rho[i]);
      if (!x.allFinite() || !f.v[i].allFinite() || !std::isfinite(rho)) {
        if (s.first_nan < 0) s.first_nan = long(i);
      } else if (f.kind[i] == 0) {
        for (int a = 0; a < D; ++a)
          if (double(x[a]) < lo[std::size_t(a)] || double(x[a]) > hi[std::size_t(a)])
            fl = 1 + std::uint8_t(RemovalRule::Domain);
        const double v2 = double(f.v[i].squaredNorm());
        if (!fl && (rho < rho_lo || rho > rho_hi)) fl = 1 + std::uint8_t(RemovalRule::Density);
        if (!fl && v2 > v2_max) fl = 1 + std::uint8_t(RemovalRule::Speed);
        if (energy && !fl) {
          const double m = f.mass[i];
          s.e.kinetic += 0.5 * m * v2;
          s.e.potential -= m * double(g.dot(x - gmin));
          s.e.internal += m * tait_internal_energy(rho, rho0_, B);
          s.e.mass += m;
        }
      }
      flag[i] = fl;
      s.flagged += fl != 0;
    }
    part[b] = s;
  });
  team_single([&] {
    flagged_ = 0;
    first_nan_ = -1;
    kept_energy_ = FluidEnergy{};
    for (long b = 0; b < nb; ++b) {  // in block order: the same sums for any thread count
      const BlockFlags& s = part[b];
      flagged_ += s.flagged;
      if (first_nan_ < 0 && s.first_nan >= 0) first_nan_ = s.first_nan;
      kept_energy_.kinetic += s.e.kinetic;
      kept_energy_.potential += s.e.potential;
      kept_energy_.internal += s.e.internal;
      kept_energy_.mass += s.e.mass;
    }
    flags_ready_ = true;
  });
}

template <int D>
void HealthMonitor<D>::clean_step(long step) {
  last_removed_.clear();
  const std::size_t slot = std::size_t(step % spec_.removal_window);
  window_sum_ -= window_[slot];
  window_[slot] = 0;
}

template <int D>
std::string HealthMonitor<D>::after_step(Simulation<D>& sim) {
  if (!started_) start(sim);
  last_removed_.clear();
  if (!flags_ready_) flag_pass(sim);  // not run inside the step's region
  flags_ready_ = false;
  const auto& f = sim.fields();
  const std::size_t n = sim.size();
  const std::uint8_t* flag = flag_.data();
  const bool energy = energy_on_;
  const long flagged = flagged_, first_nan = first_nan_;
  FluidEnergy e = kept_energy_;
  // a distributed run decides on global figures: every rank takes the same branch below, and a message
  // names the particle of the lowest rank that has one
  const bool dist = sim.distributed();
  auto agreed = [&](const std::string& local) { return dist ? parallel::first_message(sim.comm(), local) : local; };
  if (dist && energy) sum_over_ranks(sim, e);
  const std::string where = "health rule '";
  {
    std::string nan;
    if (first_nan >= 0) {
      std::ostringstream msg;
      msg << where << "nan': particle id " << f.id[std::size_t(first_nan)]
          << (f.kind[std::size_t(first_nan)] == 0 ? " (fluid)" : " (boundary)")
          << " has a non-finite position, velocity or density";
      nan = msg.str();
    }
    if (const std::string m = agreed(nan); !m.empty()) return m;
  }

  // what the removal rules found, in storage order (lowest index first: the same for any thread count)
  std::array<long, kRemovalRules> found{};
  doomed_.clear();
  std::string stop;
  if (flagged > 0)
    for (std::size_t i = 0; i < n; ++i)
      if (flag[i]) {
        const auto r = RemovalRule(flag[i] - 1);
        if (stop_) {
          stop = where + removal_rule_name(r) + "' (health.on_violation = \"stop\"): " + violation_message(sim, i, r);
          break;
        }
        ++found[std::size_t(r)];
        doomed_.push_back(std::uint32_t(i));
      }
  if (const std::string m = agreed(stop); !m.empty()) return m;
  if (dist) {
    std::int64_t c[kRemovalRules];
    for (int r = 0; r < kRemovalRules; ++r) c[r] = found[std::size_t(r)];
    sim.comm().sum(std::span<std::int64_t>(c, kRemovalRules));
    for (int r = 0; r < kRemovalRules; ++r) found[std::size_t(r)] = long(c[r]);
  }

  // rate and total: removals that are not water leaving the domain
  const long unphysical = found[1] + found[2];
  const std::size_t slot = std::size_t(sim.step() % spec_.removal_window);
  const long window_sum = window_sum_ - window_[slot] + unphysical;
  const double n0 = double(std::max<std::size_t>(n0_, 1));
  if (unphysical > 0 && double(window_sum) > spec_.max_removed_fraction * n0) {
    const auto it = std::find_if(doomed_.begin(), doomed_.end(),
                                 [&](std::uint32_t i) { return flag[i] != 1 + std::uint8_t(RemovalRule::Domain); });
    const std::string first =
        agreed(it == doomed_.end() ? std::string() : violation_message(sim, *it, RemovalRule(flag[*it] - 1)));
    return where + "rate': " + std::to_string(window_sum) + " fluid particles (" + fmt(100.0 * window_sum / n0) +
           " % of " + std::to_string(n0_) + ") left the density or speed bounds within the last " +
           std::to_string(spec_.removal_window) + " steps (health.max_removed_fraction = " +
           fmt(spec_.max_removed_fraction) + " per health.removal_window); first of this step: " + first;
  }
  const long total_unphysical = removed_[1] + removed_[2] + unphysical;
  if (unphysical > 0 && double(total_unphysical) > spec_.max_removed_total * n0)
    return where + "total': " + std::to_string(total_unphysical) + " fluid particles (" +
           fmt(100.0 * total_unphysical / n0) + " % of " + std::to_string(n0_) +
           ") removed for density or speed since the start (health.max_removed_total = " +
           fmt(spec_.max_removed_total) + ")";

  // energy of what stays
  if (energy_on_) {
    const double growth = (e.total() - e0_) / e_scale_;
    growth_max_ = std::max(growth_max_, growth);
    if (growth > spec_.max_energy_growth) {
      std::size_t fastest = 0;
      double v2 = -1;
      for (std::size_t i = 0; i < n; ++i)
        if (f.kind[i] == 0 && double(f.v[i].squaredNorm()) > v2) {
          v2 = double(f.v[i].squaredNorm());
          fastest = i;
        }
      const double v2_all = dist ? sim.comm().max(v2) : v2;
      const std::string fastest_text = agreed(v2 == v2_all && v2 >= 0 ? "particle id " + std::to_string(f.id[fastest]) +
                                                                            " at " + fmt(std::sqrt(v2)) + " m/s"
                                                                      : std::string());
      return where + "energy': the fluid's energy rose to " + fmt(e.total()) + " J (kinetic " + fmt(e.kinetic) +
             ", potential " + fmt(e.potential) + ", internal " + fmt(e.internal) + ") from " + fmt(e0_) +
             " J at the start, by " + fmt(growth) + " x the energy scale " + fmt(e_scale_) +
             " J (health.max_energy_growth = " + fmt(spec_.max_energy_growth) + "); fastest: " + fastest_text;
    }
  }

  // healthy: remove and count
  window_sum_ = window_sum;
  window_[slot] = unphysical;
  for (int r = 0; r < kRemovalRules; ++r) removed_[std::size_t(r)] += found[std::size_t(r)];
  if (!doomed_.empty() || (dist && found[0] + found[1] + found[2] > 0)) {
    for (const std::uint32_t i : doomed_) record(sim, i, RemovalRule(flag[i] - 1));
    if (dist) gather_removed(sim.comm());
    sim.remove_particles(doomed_);  // collective in a distributed run
  }
  return {};
}

template <int D>
void HealthMonitor<D>::gather_removed(parallel::Communicator& comm) {
  // every rank's records, in rank order (removed.csv is written once)
  static_assert(std::is_trivially_copyable_v<RemovedParticle>);
  std::string mine(last_removed_.size() * sizeof(RemovedParticle), '\0');
  if (!mine.empty()) std::memcpy(mine.data(), last_removed_.data(), mine.size());
  last_removed_.clear();
  for (int r = 0; r < comm.size(); ++r) {
    const std::string got = comm.broadcast(r == comm.rank() ? mine : std::string(), r);
    const std::size_t k = got.size() / sizeof(RemovedParticle);
    const std::size_t at = last_removed_.size();
    last_removed_.resize(at + k);
    if (k) std::memcpy(static_cast<void*>(last_removed_.data() + at), got.data(), k * sizeof(RemovedParticle));
  }
}

template <int D>
nlohmann::json HealthMonitor<D>::save_state() const {
  return {{"initial_fluid", n0_},         {"initial_energy", e0_},  {"energy_scale", e_scale_},
          {"max_energy_growth_seen", growth_max_}, {"removed", removed_}, {"window", window_}};
}

template <int D>
void HealthMonitor<D>::restore_state(const nlohmann::json& j) {
  if (!j.is_object() || !j.contains("initial_fluid")) return;  // a fresh start() follows
  n0_ = j.at("initial_fluid").get<std::size_t>();
  e0_ = j.at("initial_energy").get<double>();
  e_scale_ = j.at("energy_scale").get<double>();
  growth_max_ = j.value("max_energy_growth_seen", 0.0);
  removed_ = j.at("removed").get<std::array<long, kRemovalRules>>();
  const auto w = j.at("window").get<std::vector<long>>();
  if (w.size() == window_.size()) window_ = w;
  window_sum_ = 0;
  for (long c : window_) window_sum_ += c;
  started_ = true;
}

template <int D>
nlohmann::json HealthMonitor<D>::report() const {
  nlohmann::json removed = nlohmann::json::object();
  for (int r = 0; r < kRemovalRules; ++r) removed[removal_rule_name(RemovalRule(r))] = removed_[std::size_t(r)];
  return {{"on_violation", spec_.on_violation},
          {"fluid_particles_initial", n0_},
          {"removed", removed},
          {"removed_total", removed_total()},
          {"energy_rule", energy_on_ ? "on" : "off"},
          {"initial_energy", e0_},
          {"energy_scale", e_scale_},
          {"max_energy_growth_seen", growth_max_}};
}

template class HealthMonitor<2>;
template class HealthMonitor<3>;

}  // namespace varsph
