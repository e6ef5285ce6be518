#pragma once
// The device backend as the host sees it (docs/gpu.md): a mirror of the particle store on the device and
// the loops of one integrator step there. Nothing here names CUDA: the same backend is compiled twice,
// once with the CUDA launch (src/exec/cuda/, nvcc) and once with the host launch that emulates it
// (host_emulation.cpp), which is what machines without a GPU (and CI) test.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/particle_store.hpp"
#include "exec/grid_view.hpp"
#include "physics/eos.hpp"
#include "physics/physics_params.hpp"

namespace varsph::exec {

// Which integrator the device runs (the scene's integrator.type; others are refused at start).
enum class DeviceIntegratorKind { Verlet, VerletDsph, SymplecticEuler, Variational };

// Everything the backend needs from the scene and the host simulation, as plain values.
template <int D>
struct DeviceSetup {
  physics::PhysicsParams<D> params;
  physics::TaitEos eos{Real(1000), Real(1)};
  std::vector<Real> table_w, table_f;  // the tabulated kernel's nodes (kernels/tabulated.hpp)
  Real table_scale = 0;
  int table_intervals = 0;
  Real support = 0;
  GridView<D> grid{};  // configuration only (no arrays)
  // the particle store: every registered field is mirrored on the device unless host_only (fields no
  // device loop reads: they follow the device's reordering through one index per particle at download)
  std::vector<FieldBase*> fields;
  std::vector<bool> host_only;
  std::vector<std::string> position_like;  // fields shifted with the positions on periodic wraps
  std::size_t n = 0;
  // integrator
  DeviceIntegratorKind integrator = DeviceIntegratorKind::Verlet;
  int euler_every = 40;
  double alpha = 1, fp_tolerance = 0, spacing = 0;
  int fp_max_iterations = 50;
  bool halve_on_failure = false, variational_explicit = false, variational_wall = false;
  // the health rules' per-particle test (sim/health.cpp flag_pass)
  double max_density_error = 0.5, max_speed = 1e300;
  double domain_min[D] = {}, domain_max[D] = {};
};

// What the backend asks of the host side during a step (implemented over Simulation in device_run.cpp).
template <int D>
class HostSide {
 public:
  virtual ~HostSide() = default;
  // Simulation::set_skin: reconfigures the host grid (InputError when it cannot) and returns its view.
  virtual GridView<D> set_skin(Real skin) = 0;
  virtual Real skin() const = 0;
  virtual Vec<D> body_acceleration() const = 0;  // ramped gravity + body force now [m/s^2]
  virtual bool fixed_dt() const = 0;              // integrator.dt given: choose_dt needs no maxima
  // the scene's dt rule (fixed, or the CFL limits of integrators/time_step_control.hpp) for the given
  // largest fluid speed and acceleration [s]
  virtual double choose_dt(double v_max, double a_max) const = 0;
  virtual double dt() const = 0;
  virtual void set_dt(double dt) = 0;
  virtual double time() const = 0;
  virtual long step() const = 0;
};

// Integrator state that later steps depend on, saved in checkpoints under the host integrators' keys.
struct DeviceStepState {
  long steps_since_euler = -1;  // verlet_dsph
  double dt_prev = 0;           // variational
  int halvings = 0;
  long steps_since_change = 0;
  double last_bound = 0;
};
struct DeviceStepReport {
  int iterations = 0;
  double residual = 0, contraction = 0, dt_bound = 0;
};

template <int D>
class DeviceBackend {
 public:
  virtual ~DeviceBackend() = default;
  virtual const char* name() const = 0;  // "cuda" | "cuda_emulation"
  // host store -> device (every field, as many particles as the store now holds: at most the count the
  // backend was built for, since particles are only ever removed), then the device bins it
  virtual void upload() = 0;
  // device -> host store when the device is ahead (host-only fields reordered to the device's order)
  virtual void download() = 0;
  virtual bool device_ahead() const = 0;
  virtual DeviceStepReport step(DeviceStepState& state) = 0;
  // lowest particle index the health rules flag (sim/health.cpp flag_pass: a non-finite state; a fluid
  // particle outside a closed axis, the density bounds or the speed bound), or -1
  virtual std::int64_t first_unhealthy() = 0;
  // a device-side copy of the checkpointed fields (the runner's last good state), and back
  virtual void snapshot_capture() = 0;
  virtual void snapshot_restore() = 0;
  // Copies the last-good copy into the store while the next step runs (frames and checkpoints of a step
  // are written from it during the following one): begin after snapshot_capture(), finish after the next
  // step. The store then holds the captured state in every checkpointed field (the others are left as
  // they were); the device stays ahead.
  virtual void begin_snapshot_download() = 0;
  virtual void finish_snapshot_download() = 0;
  // bytes the backend holds on the device: the particle mirror (and its share of grid/sort buffers)
  // and the last-good copy separately
  virtual std::size_t state_bytes() const = 0;
  virtual std::size_t snapshot_bytes() const = 0;
};

// Factories, one per launch. The CUDA one is only in CUDA builds (cuda_compiled()).
template <int D>
std::unique_ptr<DeviceBackend<D>> make_emulation_backend(const DeviceSetup<D>& setup, HostSide<D>& host);
template <int D>
std::unique_ptr<DeviceBackend<D>> make_cuda_backend(const DeviceSetup<D>& setup, HostSide<D>& host);

// Whether this build has the CUDA backend, and whether a CUDA device is present (why not, if not).
bool cuda_compiled();
bool cuda_device_present(std::string* why);
// "NVIDIA H100 80GB HBM3, 79.1 GiB, sm_90" (empty without a device)
std::string cuda_device_description();

}  // namespace varsph::exec
