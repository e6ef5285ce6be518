#pragma once
// Runs that survive violent flows, and blow-ups that still stop (docs/results.md "Health", the health.*
// keys in docs/scene.md). Checked after every step on the new state, in this order:
//
//   nan      a particle with a non-finite position, velocity or density                  -> blow-up (exit 3)
//   domain   a fluid particle outside domain.min/max on a non-periodic axis: water that
//            left the region simulated (over a wall, through an open top)                   -> removed
//   density  a fluid particle with |rho/rho0 - 1| > health.max_density_error: outside the
//            weakly-compressible model (DualSPHysics' RhopOut, 700-1300 kg/m^3 for water)  -> removed
//   speed    a fluid particle faster than health.max_mach c0: it outruns its own pressure
//            waves, so no SPH force can act on it in time                                   -> removed
//   rate     more than health.max_removed_fraction of the initial fluid particles removed
//            by `density` or `speed` within health.removal_window steps                     -> blow-up
//   total    more than health.max_removed_total of them over the run                        -> blow-up
//   energy   total fluid energy E = kinetic + potential + internal (seed eq. 16-17) above
//            E0 + health.max_energy_growth x E_scale                                        -> blow-up
//
// With health.on_violation = "stop" the domain, density and speed rules are blow-ups too (the strict
// behaviour of earlier versions). E_scale = KE0 + |PE0| + IE0 + M (c0/10)^2 / 2: the initial energy plus
// the kinetic energy of all the fluid moving at c0/10, the largest speed the c0 = 10 U rule plans for
// (so a fluid at rest without gravity has a scale). The energy rule is off where energy enters legitimately
// (a boundary body with prescribed motion, a body force) and with health.max_energy_growth = 0.
//
// Everything here is deterministic and independent of the thread count: per-particle decisions, sums over
// fixed blocks added in order, removals in storage order. A blow-up leaves the state of the failing step
// untouched (nothing removed) for the runner's last-good-state handling.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/simulation.hpp"

namespace varsph {

// The rules that remove particles, in the order of the diagnostics.csv columns.
enum class RemovalRule : int { Domain = 0, Density = 1, Speed = 2 };
inline constexpr int kRemovalRules = 3;
const char* removal_rule_name(RemovalRule r);  // "domain", "density", "speed"

// One removed particle as it was when the rule fired (removed.csv).
struct RemovedParticle {
  long step = 0;
  double time = 0;
  std::int64_t id = 0;
  RemovalRule rule = RemovalRule::Domain;
  std::array<double, 3> x{}, v{};
  double rho = 0, p = 0;
  int fluid_neighbours = 0, boundary_neighbours = 0;  // within the kernel support when removed
};

// Total fluid energy by parts [J; J/m in 2D]: sum m |v|^2/2, -sum m g.(x - domain.min), sum m pi(rho).
struct FluidEnergy {
  double kinetic = 0, potential = 0, internal = 0, mass = 0;
  double total() const { return kinetic + potential + internal; }
};

template <int D>
class HealthMonitor {
 public:
  explicit HealthMonitor(const scene::Scene& s);

  // Reference of a fresh run: the initial fluid particle count and energy.
  void start(const Simulation<D>& sim);
  // After each step. Applies the removal rules and returns "" or, for a blow-up, the message naming the
  // rule, the particle or the figures (the state is then left as the step made it).
  std::string after_step(Simulation<D>& sim);
  // A step the device's per-particle test found clean (exec/: a device run calls after_step only on a step
  // with a flagged particle): nothing removed at `step`, which keeps the removal window's count exact. The
  // energy rule is not evaluated on such steps (it would need the state on the host every step).
  void clean_step(long step);
  // The per-particle part of after_step (flags, the energy of the fluid that stays) on the state after a
  // step. Every thread of a step's parallel region may call it (core/team.hpp: Simulation::advance runs it
  // there, saving the check its own fork/join); after_step uses its result, or runs it itself.
  void flag_pass(const Simulation<D>& sim);

  // Particles removed by the last after_step() (for removed.csv and the first-removal warning).
  const std::vector<RemovedParticle>& last_removed() const { return last_removed_; }
  // Cumulative counts per rule since the start of the run (restarts continue them).
  const std::array<long, kRemovalRules>& removed() const { return removed_; }
  long removed_total() const { return removed_[0] + removed_[1] + removed_[2]; }
  std::size_t initial_fluid() const { return n0_; }
  bool energy_rule_active() const { return energy_on_; }
  double energy_scale() const { return e_scale_; }
  double initial_energy() const { return e0_; }
  // Largest (E - E0) / E_scale seen so far (run.json).
  double max_energy_growth_seen() const { return growth_max_; }

  // State that later decisions depend on (checkpoint runner_state: restarts decide as a straight run).
  nlohmann::json save_state() const;
  void restore_state(const nlohmann::json& j);
  // run.json "health" block: the rules as resolved and what they did.
  nlohmann::json report() const;

  // Fluid energy of the current state, summed over fixed blocks in order (any thread count, same bits);
  // particles with flag != 0 in `skip` (may be null) are left out.
  FluidEnergy fluid_energy(const Simulation<D>& sim, const std::uint8_t* skip = nullptr) const;

 private:
  std::string violation_message(const Simulation<D>& sim, std::size_t i, RemovalRule r) const;
  // Distributed: last_removed_ becomes every rank's records in rank order, on every rank (collective).
  void gather_removed(parallel::Communicator& comm);
  void record(const Simulation<D>& sim, std::size_t i, RemovalRule r);

  scene::HealthSpec spec_;
  double rho0_, c0_;
  std::vector<double> dmin_, dmax_;
  std::vector<bool> periodic_;
  bool stop_ = false, energy_on_ = true;
  std::size_t n0_ = 0;
  double e0_ = 0, e_scale_ = 0, growth_max_ = 0;
  std::array<long, kRemovalRules> removed_{};
  std::vector<long> window_;  // density + speed removals of the last removal_window steps (ring)
  long window_sum_ = 0;
  std::vector<std::uint8_t> flag_;      // per particle: 0 healthy, 1 + RemovalRule (sized once, grows)
  std::vector<std::uint32_t> doomed_;   // storage indices to remove this step
  std::vector<RemovedParticle> last_removed_;
  struct BlockFlags {
    long flagged = 0;
    long first_nan = -1;
    FluidEnergy e;  // of the fluid particles not flagged
  };
  std::vector<BlockFlags> block_part_;          // per fixed block of particles (scratch, grows once)
  mutable std::vector<FluidEnergy> energy_part_;  // idem
  bool started_ = false;
  // flag_pass result for after_step
  bool flags_ready_ = false;
  long flagged_ = 0, first_nan_ = -1;
  FluidEnergy kept_energy_;
};

}  // namespace varsph
