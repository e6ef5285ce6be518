// The device backend through the CUDA launch (execution.device = "cuda"; docs/gpu.md), and the device query.
#include <cuda_runtime.h>

#include <cstdio>

#include "exec/backend_impl.hpp"
#include "exec/cuda/cuda_launch.cuh"

namespace varsph::exec {

bool cuda_compiled() { return true; }

bool cuda_device_present(std::string* why) {
  int n = 0;
  const cudaError_t e = cudaGetDeviceCount(&n);
  if (e != cudaSuccess) {
    cudaGetLastError();
    if (why) *why = std::string("cudaGetDeviceCount: ") + cudaGetErrorName(e) + ", " + cudaGetErrorString(e);
    return false;
  }
  if (n == 0) {
    if (why) *why = "cudaGetDeviceCount found no device";
    return false;
  }
  cudaDeviceProp prop{};
  if (cudaGetDeviceProperties(&prop, 0) == cudaSuccess && prop.major * 10 + prop.minor < VARSPH_CUDA_MIN_ARCH) {
    if (why)
      *why = std::string(prop.name) + " has compute capability " + std::to_string(prop.major) + "." +
             std::to_string(prop.minor) + ", this build targets sm_" + std::to_string(VARSPH_CUDA_MIN_ARCH) +
             " (configure with -DCMAKE_CUDA_ARCHITECTURES=" + std::to_string(prop.major * 10 + prop.minor) + ")";
    return false;
  }
  return true;
}

std::string cuda_device_description() {
  std::string why;
  if (!cuda_device_present(&why)) return {};
  cudaDeviceProp prop{};
  if (cudaGetDeviceProperties(&prop, 0) != cudaSuccess) return {};
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s, %.1f GiB, sm_%d%d", prop.name, double(prop.totalGlobalMem) / double(1 << 30),
                prop.major, prop.minor);
  return buf;
}

template <int D>
std::unique_ptr<DeviceBackend<D>> make_cuda_backend(const DeviceSetup<D>& setup, HostSide<D>& host) {
  return std::make_unique<Backend<D, CudaLaunch>>(setup, host);
}

template std::unique_ptr<DeviceBackend<2>> make_cuda_backend<2>(const DeviceSetup<2>&, HostSide<2>&);
template std::unique_ptr<DeviceBackend<3>> make_cuda_backend<3>(const DeviceSetup<3>&, HostSide<3>&);

}  // namespace varsph::exec
