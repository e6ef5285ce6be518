#include "sim/restart.hpp"

#include "bodies/rigid_bodies.hpp"

#include <cstring>
#include <map>

#include "core/errors.hpp"
#include "exec/device_backend.hpp"

namespace varsph {
namespace {

// Rigid body states (poses, velocities) live beside the particle store: saved with the integrator state.
template <int D>
void restore_rigid_bodies(Simulation<D>& sim, const nlohmann::json& state, const std::string& file) {
  auto* b = sim.rigid_bodies();
  if (!b) return;
  if (!state.contains("rigid_bodies"))
    throw InputError(file + ": the checkpoint holds no rigid body state (written by a varsph without rigid bodies?)");
  b->restore_state(state.at("rigid_bodies"));
}

// A paddle's active absorption (motion.awas): its correction's state, saved with the integrator state.
template <int D>
void restore_absorption(Simulation<D>& sim, const nlohmann::json& state, const std::string& file) {
  if (!sim.motion().absorbing()) return;
  if (!state.contains("wavemaker_absorption"))
    throw InputError(file + ": the checkpoint holds no active absorption state (written without motion.awas?)");
  sim.restore_motion_state(state.at("wavemaker_absorption"));
}

}  // namespace
namespace {

// Flattens a JSON value into dotted keys (objects and arrays both descend; arrays by index).
void flatten(const nlohmann::json& j, const std::string& prefix, std::map<std::string, nlohmann::json>& out) {
  if (j.is_object() && !j.empty()) {
    for (auto it = j.begin(); it != j.end(); ++it) flatten(it.value(), prefix.empty() ? it.key() : prefix + "." + it.key(), out);
  } else if (j.is_array() && !j.empty() && prefix != "probes") {
    for (std::size_t k = 0; k < j.size(); ++k) flatten(j[k], prefix + "." + std::to_string(k), out);
  } else {
    out[prefix] = j;
  }
}

bool starts_with(const std::string& s, const std::string& p) { return s.compare(0, p.size(), p) == 0; }

// Boundary particles (kind != 0) in a checkpoint's `kind` array; InputError when it is missing or malformed.
std::size_t checkpoint_boundary_count(const io::Checkpoint& c, std::size_t particles, const std::string& where) {
  const io::CheckpointArray* k = c.find("kind");
  if (!k || k->type != ScalarType::Int32 || k->components != 1 || k->bytes.size() != particles * sizeof(std::int32_t))
    throw InputError(where + "particle field 'kind' is missing or has another type or shape");
  std::size_t n = 0;
  for (std::size_t i = 0; i < particles; ++i) {
    std::int32_t v;
    std::memcpy(&v, k->bytes.data() + i * sizeof v, sizeof v);
    n += v != 0;
  }
  return n;
}

// What a state snapshot copies: the checkpointed fields and, in a distributed run, the order tags that
// give the serial summation order (parallel/domain.hpp).
bool in_snapshot(const FieldBase& f) { return f.flags().checkpointed || f.name() == "parallel_order_tag"; }

}  // namespace

bool restart_may_change(const std::string& k) {
  // `setup` (issue 35) only names where the method keys' values came from; the values themselves are compared
  return k == "setup" || k == "time.end" || k == "particles.max_count" || k == "output" || starts_with(k, "output.") || k == "checkpoint" ||
         starts_with(k, "checkpoint.") || k == "probes" || starts_with(k, "probes.") || k == "log" ||
         starts_with(k, "log.") || k == "parallel" || starts_with(k, "parallel.") || k == "execution" ||
         starts_with(k, "execution.");  // cpu <-> cuda restarts
}

std::string first_physics_difference(const nlohmann::json& a, const nlohmann::json& b) {
  std::map<std::string, nlohmann::json> fa, fb;
  flatten(a, "", fa);
  flatten(b, "", fb);
  auto ia = fa.begin(), ib = fb.begin();
  // merge walk over the sorted keys of both
  while (ia != fa.end() || ib != fb.end()) {
    if (ib == fb.end() || (ia != fa.end() && ia->first < ib->first)) {
      if (!restart_may_change(ia->first)) return ia->first;
      ++ia;
    } else if (ia == fa.end() || ib->first < ia->first) {
      if (!restart_may_change(ib->first)) return ib->first;
      ++ib;
    } else {
      if (ia->second != ib->second && !restart_may_change(ia->first)) return ia->first;
      ++ia;
      ++ib;
    }
  }
  return {};
}

template <int D>
void restore_from_checkpoint(Simulation<D>& sim, const io::Checkpoint& c, const std::string& file) {
  const auto& h = c.header;
  const std::string where = file + ": ";
  if (h.dimension != D)
    throw InputError(where + "checkpoint of a " + std::to_string(h.dimension) + "D scene, but the scene '" +
                     sim.scene().file.string() + "' is " + std::to_string(D) + "D");
  if (h.real_type != VARSPH_REAL_NAME)
    throw InputError(where + "checkpoint written by a build with Real = " + h.real_type + ", this build uses " +
                     VARSPH_REAL_NAME + " (a restart would not be bitwise)");
  if (const std::string k = first_physics_difference(h.scene, sim.scene().resolved); !k.empty()) {
    const auto ptr = nlohmann::json::json_pointer("/" + [&] {
      std::string p = k;
      for (char& ch : p) if (ch == '.') ch = '/';
      return p;
    }());
    const std::string was = h.scene.contains(ptr) ? h.scene.at(ptr).dump() : "(absent)";
    const std::string now = sim.scene().resolved.contains(ptr) ? sim.scene().resolved.at(ptr).dump() : "(absent)";
    throw InputError(where + "the scene's physics differs from the checkpoint's at key '" + k + "' (checkpoint: " +
                     was + ", scene: " + now + "); only time.end, output.*, checkpoint.*, probes, log.* and particles.max_count may "
                     "change on restart");
  }
  // a checkpoint written after fluid particles were removed (health.*) holds fewer fluid particles than
  // the scene builds; boundary particles are never removed, so their count must match. In a distributed
  // run this process holds rows [first_row, first_row + rows) of the checkpoint; the counts are global.
  // (inlets create particles: a scene with open boundaries may hold more or fewer than it builds)
  if (const std::int64_t built = sim.global_count(); h.particles > built && sim.scene().open_boundaries.empty())
    throw InputError(where + "checkpoint has " + std::to_string(h.particles) + " particles, the scene builds " +
                     std::to_string(built));
  const std::size_t ckpt_boundary =
      std::size_t(sim.global_sum(double(checkpoint_boundary_count(c, std::size_t(c.rows), where))));
  if (ckpt_boundary != sim.count(1))
    throw InputError(where + "checkpoint has " + std::to_string(ckpt_boundary) + " boundary particles, the scene builds " +
                     std::to_string(sim.count(1)) + " (" + std::to_string(h.particles) + " particles in all, the scene " +
                     std::to_string(sim.global_count()) + ")");
  if (h.integrator != sim.integrator().name())
    throw InputError(where + "checkpoint was written by the '" + h.integrator + "' integrator, the scene uses '" +
                     sim.integrator().name() + "'");
  // every checkpointed field of this build must be in the file with the same shape and type
  for (const auto& f : sim.store().fields()) {
    if (!f->flags().checkpointed) continue;
    const io::CheckpointArray* a = c.find(f->name());
    if (!a) throw InputError(where + "particle field '" + f->name() + "' is missing from the checkpoint");
    if (a->type != f->scalar_type() || a->components != f->components() ||
        a->bytes.size() != f->bytes_per_particle() * std::size_t(c.rows))
      throw InputError(where + "particle field '" + f->name() + "' has another type or shape in the checkpoint");
  }
  // this process's rows of the checkpoint (all of them in one process; a share in a distributed run,
  // which the sort below sends to their owners)
  sim.adopt_rows(std::size_t(c.rows), c.first_row);
  for (const auto& f : sim.store().fields()) {
    if (!f->flags().checkpointed) continue;
    const io::CheckpointArray* a = c.find(f->name());
    if (!a->bytes.empty()) std::memcpy(f->raw(), a->bytes.data(), a->bytes.size());
  }
  sim.recount_kinds();
  sim.set_clock(h.time, long(h.step));
  restore_rigid_bodies(sim, h.integrator_state, file);  // before the sort places their particles
  restore_absorption(sim, h.integrator_state, file);     // the paddles' correction: before the sort moves them
  // id counter and flows (in the runner state: in a distributed run their sums agree to round-off only)
  sim.restore_flow_state(h.runner_state.value("flow", nlohmann::json()));
  // the arrays are in the order of the checkpointed step's cell sort; sorting again is stable, so this
  // rebuilds the neighbour grid for them without changing the order (checked by the restart tests)
  sim.sort_and_bin();
  sim.set_dt(h.dt);
  sim.integrator().restore_state(h.integrator_state);
  sim.host_state_changed();  // a device run continues from the restored store
}

template <int D>
io::CheckpointHeader checkpoint_header(Simulation<D>& sim, const nlohmann::json& runner_state) {
  io::CheckpointHeader h;
  h.program_version = VARSPH_VERSION;
  h.real_type = VARSPH_REAL_NAME;
  h.dimension = D;
  h.step = sim.step();
  h.time = sim.time();
  h.dt = sim.dt();
  h.particles = sim.global_count();
  h.scene = sim.scene().resolved;
  auto& integ = sim.integrator();
  h.integrator = integ.name();
  h.integrator_state = integ.save_state();
  if (const auto* b = sim.rigid_bodies()) h.integrator_state["rigid_bodies"] = b->save_state();
  if (sim.motion().absorbing()) h.integrator_state["wavemaker_absorption"] = sim.save_motion_state();
  h.runner_state = runner_state;
  h.runner_state["flow"] = sim.save_flow_state();
  return h;
}

template <int D>
void StateSnapshot<D>::capture(Simulation<D>& sim, const nlohmann::json& runner_state) {
  const auto& fields = sim.store().fields();
  stored_ = sim.store().size();  // owned particles and, in a distributed run, ghosts
  owned_ = sim.size();
  buffers_.resize(sim.on_device() ? 0 : fields.size());
  if (sim.on_device()) {  // a device run keeps its copy on the device (no transfer per step)
    sim.device()->snapshot_capture();
    device_bytes_ = sim.device()->snapshot_bytes();
  }
  for (std::size_t k = 0; k < buffers_.size(); ++k) {
    const auto& f = fields[k];
    if (!in_snapshot(*f)) continue;
    const std::size_t n = f->bytes_per_particle() * f->size();
    buffers_[k].resize(n);  // no reallocation after the first capture
    if (n) std::memcpy(buffers_[k].data(), f->raw(), n);
  }
  time_ = sim.time();
  dt_ = sim.dt();
  step_ = sim.step();
  integrator_state_ = sim.integrator().save_state();
  if (const auto* b = sim.rigid_bodies()) integrator_state_["rigid_bodies"] = b->save_state();
  if (sim.motion().absorbing()) integrator_state_["wavemaker_absorption"] = sim.save_motion_state();
  integrator_state_["flow"] = sim.save_flow_state();
  runner_state_ = runner_state;
  valid_ = true;
}

template <int D>
void StateSnapshot<D>::restore(Simulation<D>& sim) const {
  if (sim.on_device()) sim.device()->snapshot_restore();  // device runs remove no particles (docs/gpu.md)
  // particles removed after the capture (health.*) come back with the rest of the state; a distributed
  // step may have moved particles between ranks: back to the captured rows
  else sim.store().resize(stored_);
  const auto& fields = sim.store().fields();
  for (std::size_t k = 0; k < fields.size() && k < buffers_.size(); ++k) {
    const auto& f = fields[k];
    if (!in_snapshot(*f) || buffers_[k].size() != f->bytes_per_particle() * f->size()) continue;
    if (!buffers_[k].empty()) std::memcpy(f->raw(), buffers_[k].data(), buffers_[k].size());
  }
  sim.set_clock(time_, step_);
  sim.set_dt(dt_);
  restore_rigid_bodies(sim, integrator_state_, "the last good state");
  restore_absorption(sim, integrator_state_, "the last good state");
  sim.integrator().restore_state(integrator_state_);
  sim.restore_flow_state(integrator_state_.at("flow"));
  if (sim.distributed()) {  // owned rows back in place, ghosts and grid rebuilt for them (collective)
    sim.adopt_rows(owned_, -1);  // with the captured order tags: the serial summation order
    sim.recount_kinds();
    sim.rebin();
  } else {
    sim.recount_kinds();
  }
}

template <int D>
long StateSnapshot<D>::replay_to(Simulation<D>& sim, long step) const {
  if (sim.on_device()) sim.device()->snapshot_restore();  // the device's own copy, binned there
  // particles removed after the capture come back; a distributed step may have moved particles
  // between ranks: back to the captured rows (owned first, ghosts after them)
  else sim.store().resize(stored_);
  const auto& fields = sim.store().fields();
  for (std::size_t k = 0; k < fields.size() && k < buffers_.size(); ++k) {
    const auto& f = fields[k];
    if (!in_snapshot(*f) || buffers_[k].size() != f->bytes_per_particle() * f->size()) continue;
    if (!buffers_[k].empty()) std::memcpy(f->raw(), buffers_[k].data(), buffers_[k].size());
  }
  if (sim.distributed()) sim.adopt_rows(owned_, -1);  // ghosts dropped, order tags kept (collective below)
  sim.recount_kinds();
  // the order of restore_from_checkpoint(): the arrays are in the captured step's cell order, and the
  // stable sort rebuilds its grid without moving them
  sim.set_clock(time_, step_);
  restore_rigid_bodies(sim, integrator_state_, "the last good state");
  restore_absorption(sim, integrator_state_, "the last good state");  // before the sort places them
  sim.restore_flow_state(integrator_state_.at("flow"));
  if (!sim.on_device()) sim.sort_and_bin();
  sim.set_dt(dt_);
  sim.integrator().restore_state(integrator_state_);
  long replayed = 0;
  for (; sim.step() < step; ++replayed) sim.advance();
  return replayed;
}

template <int D>
std::size_t StateSnapshot<D>::bytes() const {
  std::size_t b = device_bytes_;
  for (const auto& v : buffers_) b += v.size();
  return b;
}

template void restore_from_checkpoint<2>(Simulation<2>&, const io::Checkpoint&, const std::string&);
template void restore_from_checkpoint<3>(Simulation<3>&, const io::Checkpoint&, const std::string&);
template io::CheckpointHeader checkpoint_header<2>(Simulation<2>&, const nlohmann::json&);
template io::CheckpointHeader checkpoint_header<3>(Simulation<3>&, const nlohmann::json&);
template class StateSnapshot<2>;
template class StateSnapshot<3>;

}  // namespace varsph
