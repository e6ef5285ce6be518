#pragma once
// Restart support: checking a checkpoint against the scene, restoring a simulation from it, and the
// in-memory copy of the last good state kept for blow-up handling.
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/checkpoint.hpp"
#include "sim/simulation.hpp"

namespace varsph {

// Keys of the resolved scene that may differ between a checkpoint and the scene it is restarted with
// (CONTRACT.md "Restart"): time.end, output.*, checkpoint.*, probes, log.*, execution.* (a GPU run continues
// on the CPU and back).
bool restart_may_change(const std::string& dotted_key);

// The first key (dotted, in sorted order) whose value differs between two resolved scenes, ignoring
// the keys restart_may_change(); empty if the physics is the same.
std::string first_physics_difference(const nlohmann::json& checkpoint_scene, const nlohmann::json& scene);

// Validates the checkpoint against the simulation built from `scene` (dimension, real type, physics,
// particle count, field names/types/components) and copies its state in: every checkpointed field in
// storage order, time, step, dt and the integrator state. InputError (exit 2) naming the file and the
// mismatch; the simulation is untouched when validation fails.
template <int D>
void restore_from_checkpoint(Simulation<D>& sim, const io::Checkpoint& c, const std::string& file);

// Header for a checkpoint of the simulation's current state.
template <int D>
io::CheckpointHeader checkpoint_header(Simulation<D>& sim, const nlohmann::json& runner_state);

// A copy of everything a checkpoint holds, in preallocated buffers (no allocation after the first
// capture), so that a blow-up can write the last good frame and checkpoint. The runner takes it every
// few steps, not before each one: replay_to() restores it and advances to the last good step again,
// which reproduces that step bit for bit (the steps are deterministic for any thread count).
template <int D>
class StateSnapshot {
 public:
  void capture(Simulation<D>& sim, const nlohmann::json& runner_state);
  // Puts the captured state back into the simulation (same fields; particles removed since come back).
  void restore(Simulation<D>& sim) const;
  // restore(), the neighbour grid rebuilt as a restart from a checkpoint does, then sim.advance() until
  // sim.step() == step (>= the captured step). Returns the number of steps replayed.
  long replay_to(Simulation<D>& sim, long step) const;
  bool valid() const { return valid_; }
  long step() const { return step_; }
  const nlohmann::json& runner_state() const { return runner_state_; }
  std::size_t bytes() const;

 private:
  std::vector<std::vector<std::byte>> buffers_;
  std::size_t device_bytes_ = 0;  // a device run's copy lives on the device
  double time_ = 0, dt_ = 0;
  long step_ = 0;
  std::size_t stored_ = 0, owned_ = 0;
  nlohmann::json integrator_state_, runner_state_;
  bool valid_ = false;
};

}  // namespace varsph
