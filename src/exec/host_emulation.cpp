// The device backend through the host launch (execution.device = "cuda_emulation"; docs/gpu.md): the same
// backend code as the CUDA build, its loops run on the CPU with the CUDA launch's indexing. This is how
// machines without a GPU, CI included, test the device code.
#include "exec/backend_impl.hpp"
#include "exec/host_launch.hpp"

namespace varsph::exec {

template <int D>
std::unique_ptr<DeviceBackend<D>> make_emulation_backend(const DeviceSetup<D>& setup, HostSide<D>& host) {
  return std::make_unique<Backend<D, HostLaunch>>(setup, host);
}

template std::unique_ptr<DeviceBackend<2>> make_emulation_backend<2>(const DeviceSetup<2>&, HostSide<2>&);
template std::unique_ptr<DeviceBackend<3>> make_emulation_backend<3>(const DeviceSetup<3>&, HostSide<3>&);

}  // namespace varsph::exec
