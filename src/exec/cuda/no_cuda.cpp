// Builds without the CUDA backend (no nvcc at configure time, or -DVARSPH_CUDA=OFF): execution.device =
// "cuda" is refused at start (exec/device_run.cpp) with this build's reason.
#include <stdexcept>
#include <string>

#include "exec/device_backend.hpp"

namespace varsph::exec {

bool cuda_compiled() { return false; }

bool cuda_device_present(std::string* why) {
  if (why) *why = "this build has no CUDA backend";
  return false;
}

std::string cuda_device_description() { return {}; }

template <int D>
std::unique_ptr<DeviceBackend<D>> make_cuda_backend(const DeviceSetup<D>&, HostSide<D>&) {
  throw std::logic_error("make_cuda_backend: this build has no CUDA backend");
}

template std::unique_ptr<DeviceBackend<2>> make_cuda_backend<2>(const DeviceSetup<2>&, HostSide<2>&);
template std::unique_ptr<DeviceBackend<3>> make_cuda_backend<3>(const DeviceSetup<3>&, HostSide<3>&);

}  // namespace varsph::exec
