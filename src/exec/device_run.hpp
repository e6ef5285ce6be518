#pragma once
// A simulation's device run (docs/gpu.md): the device backend of execution.device = "cuda" (or its host
// launch, "cuda_emulation"), the host side it calls back (grid skin, dt rule, gravity ramp) and the
// integrator that steps on the device. Simulation owns one when the scene names a device.
#include <memory>
#include <string>

#include "exec/device_backend.hpp"
#include "neighbors/neighbor_grid.hpp"
#include "scene/scene.hpp"

namespace varsph {
template <int D>
class Simulation;
template <int D>
class Integrator;
}  // namespace varsph

namespace varsph::exec {

// InputError (exit 2) when the scene names a device this build or machine does not have, or a term,
// integrator or option the device does not run yet (the message names the key). Reads the scene only:
// called before any particle is built.
void check_device_scene(const scene::Scene& s);

// The device loops' description of the host's cell grid (same cells, stencil and periodic images).
template <int D>
GridView<D> grid_view_of(const NeighborGrid<D>& grid);

template <int D>
class DeviceRun {
 public:
  // Mirrors the simulation's store on the device (its host integrator initialised) and returns with the
  // device current. `host_integrator` is the scene's integrator after initialize(); its state carries over.
  DeviceRun(Simulation<D>& sim, std::unique_ptr<Integrator<D>> host_integrator);
  ~DeviceRun();
  DeviceBackend<D>& backend() { return *backend_; }
  // The integrator Simulation steps with: the host integrator's name and checkpoint state, the device's loops.
  std::unique_ptr<Integrator<D>> take_integrator();

 private:
  std::unique_ptr<HostSide<D>> host_;
  std::unique_ptr<DeviceBackend<D>> backend_;
  std::unique_ptr<Integrator<D>> integrator_;
};

// The first problem of a device run's state (sim/diagnostics.cpp check_health, reduced on the device; the
// message is the host's after a download), or an empty string.
template <int D>
std::string check_device_health(Simulation<D>& sim);

}  // namespace varsph::exec
