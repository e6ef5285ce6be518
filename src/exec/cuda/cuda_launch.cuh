#pragma once
// The CUDA launch of the device loops (docs/gpu.md): one thread per index in blocks of kBlock, two-pass
// block reductions, cub's stable radix sort, device memory, one stream. The host launch (host_launch.hpp)
// has the same interface and indexing; the backend (backend_impl.hpp) is written against either.
#include <cuda_runtime.h>

#include <cub/device/device_radix_sort.cuh>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/errors.hpp"
#include "exec/loop_bodies.hpp"

namespace varsph::exec {
namespace cuda_detail {

constexpr unsigned kBlock = 256;
constexpr unsigned kReduceBlocks = 1024;

inline void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess)
    throw std::runtime_error(std::string("CUDA: ") + what + ": " + cudaGetErrorName(e) + " (" + cudaGetErrorString(e) + ")");
}

template <class Body>
__global__ void for_each_kernel(std::size_t n, Body body) {
  const std::size_t i = std::size_t(blockIdx.x) * kBlock + threadIdx.x;
  if (i < n) body(i);
}

// Block tree over shared memory, the order the host launch emulates.
template <class Op>
__device__ typename Op::T block_tree(typename Op::T* sh) {
  __syncthreads();
  for (unsigned s = kBlock / 2; s > 0; s >>= 1) {
    if (threadIdx.x < s) sh[threadIdx.x] = Op::combine(sh[threadIdx.x], sh[threadIdx.x + s]);
    __syncthreads();
  }
  return sh[0];
}

template <class Op, class Body>
__global__ void reduce_kernel(std::size_t n, Body body, typename Op::T* partial) {
  __shared__ typename Op::T sh[kBlock];
  typename Op::T acc = Op::identity();
  for (std::size_t i = std::size_t(blockIdx.x) * kBlock + threadIdx.x; i < n; i += std::size_t(gridDim.x) * kBlock)
    acc = Op::combine(acc, body(i));
  sh[threadIdx.x] = acc;
  const typename Op::T r = block_tree<Op>(sh);
  if (threadIdx.x == 0) partial[blockIdx.x] = r;
}

template <class Op>
__global__ void reduce_final(unsigned m, typename Op::T* partial) {
  __shared__ typename Op::T sh[kBlock];
  typename Op::T acc = Op::identity();
  for (unsigned i = threadIdx.x; i < m; i += kBlock) acc = Op::combine(acc, partial[i]);
  sh[threadIdx.x] = acc;
  const typename Op::T r = block_tree<Op>(sh);
  if (threadIdx.x == 0) partial[0] = r;
}

}  // namespace cuda_detail

class CudaLaunch {
 public:
  static constexpr std::size_t kBlock = cuda_detail::kBlock;
  static const char* name() { return "cuda"; }

  CudaLaunch() {
    cuda_detail::check(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking), "creating a stream");
    cuda_detail::check(cudaMalloc(&partial_, cuda_detail::kReduceBlocks * sizeof(std::uint64_t)), "cudaMalloc");
    cuda_detail::check(cudaMallocHost(&result_, sizeof(std::uint64_t)), "cudaMallocHost");
  }
  CudaLaunch(const CudaLaunch&) = delete;
  CudaLaunch& operator=(const CudaLaunch&) = delete;
  ~CudaLaunch() {
    cudaStreamSynchronize(stream_);
    if (copy_stream_) {
      cudaStreamSynchronize(copy_stream_);
      cudaStreamDestroy(copy_stream_);
      cudaEventDestroy(ready_);
    }
    for (void* p : pinned_) cudaHostUnregister(p);
    release(sort_temp_);
    cudaFree(partial_);
    cudaFreeHost(result_);
    cudaStreamDestroy(stream_);
  }

  // --- memory ------------------------------------------------------------------------------------
  void* alloc(std::size_t bytes) {
    if (bytes == 0) return nullptr;
    void* p = nullptr;
    const cudaError_t e = cudaMalloc(&p, bytes);
    if (e == cudaErrorMemoryAllocation) {
      cudaGetLastError();
      std::size_t free_b = 0, total_b = 0;
      cudaMemGetInfo(&free_b, &total_b);
      throw InputError("the CUDA device has no room for " + std::to_string(bytes >> 20) + " MiB more (" +
                       std::to_string(free_b >> 20) + " of " + std::to_string(total_b >> 20) +
                       " MiB free): the scene has too many particles for this GPU");
    }
    cuda_detail::check(e, "cudaMalloc");
    in_use_ += bytes;
    sizes_[p] = bytes;
    return p;
  }
  void release(void* p) {
    if (!p) return;
    if (auto it = sizes_.find(p); it != sizes_.end()) {
      in_use_ -= it->second;
      sizes_.erase(it);
    }
    cudaFree(p);
  }
  void to_device(void* dst, const void* src, std::size_t bytes) {
    if (bytes) cuda_detail::check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyHostToDevice, stream_), "copy to device");
  }
  void to_host(void* dst, const void* src, std::size_t bytes) {
    if (!bytes) return;
    cuda_detail::check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyDeviceToHost, stream_), "copy to host");
    synchronize();
  }
  void copy(void* dst, const void* src, std::size_t bytes) {
    if (bytes) cuda_detail::check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyDeviceToDevice, stream_), "device copy");
  }
  void synchronize() { cuda_detail::check(cudaStreamSynchronize(stream_), "stream synchronize"); }

  // Device -> host copies on a second stream, ordered after the loops launched so far and overlapping
  // those launched later; wait_host_async() waits for them. The host memory should be pinned (pin()),
  // otherwise the driver stages the copy and it does not overlap.
  void to_host_async(void* dst, const void* src, std::size_t bytes) {
    if (!bytes) return;
    if (!copy_stream_) {
      cuda_detail::check(cudaStreamCreateWithFlags(&copy_stream_, cudaStreamNonBlocking), "creating a copy stream");
      cuda_detail::check(cudaEventCreateWithFlags(&ready_, cudaEventDisableTiming), "creating an event");
    }
    cuda_detail::check(cudaEventRecord(ready_, stream_), "event record");
    cuda_detail::check(cudaStreamWaitEvent(copy_stream_, ready_, 0), "stream wait");
    cuda_detail::check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyDeviceToHost, copy_stream_), "async copy to host");
  }
  void wait_host_async() {
    if (copy_stream_) cuda_detail::check(cudaStreamSynchronize(copy_stream_), "copy stream synchronize");
  }
  // Page-locks host memory for asynchronous copies (best effort: unpinned memory still copies, synchronously).
  void pin(void* p, std::size_t bytes) {
    if (p && bytes && cudaHostRegister(p, bytes, cudaHostRegisterDefault) == cudaSuccess) pinned_.push_back(p);
    cudaGetLastError();
  }
  void unpin(void* p) {
    for (auto it = pinned_.begin(); it != pinned_.end(); ++it)
      if (*it == p) {
        cudaHostUnregister(p);
        pinned_.erase(it);
        return;
      }
  }

  // --- loops ---------------------------------------------------------------------------------------
  template <class Body>
  void for_each(std::size_t n, const Body& body) {
    if (n == 0) return;
    const unsigned blocks = unsigned((n + kBlock - 1) / kBlock);
    cuda_detail::for_each_kernel<Body><<<blocks, unsigned(kBlock), 0, stream_>>>(n, body);
    cuda_detail::check(cudaGetLastError(), "kernel launch");
  }

  template <class Op, class Body>
  typename Op::T reduce(std::size_t n, const Body& body) {
    using T = typename Op::T;
    static_assert(sizeof(T) <= sizeof(std::uint64_t), "reduction type too large for the partials");
    T* partial = static_cast<T*>(partial_);
    const std::size_t want = (n + kBlock - 1) / kBlock;
    const unsigned blocks = unsigned(want < 1 ? 1 : (want > cuda_detail::kReduceBlocks ? cuda_detail::kReduceBlocks : want));
    cuda_detail::reduce_kernel<Op, Body><<<blocks, unsigned(kBlock), 0, stream_>>>(n, body, partial);
    cuda_detail::reduce_final<Op><<<1, unsigned(kBlock), 0, stream_>>>(blocks, partial);
    cuda_detail::check(cudaGetLastError(), "reduction launch");
    cuda_detail::check(cudaMemcpyAsync(result_, partial, sizeof(T), cudaMemcpyDeviceToHost, stream_), "reduction result");
    synchronize();
    return *static_cast<T*>(result_);
  }

  // Stable radix sort of (key, value) pairs on the low `bits` key bits (cub::DeviceRadixSort); its
  // temporary storage grows once to the largest size seen.
  void sort_pairs(const std::uint32_t* keys_in, std::uint32_t* keys_out, const std::uint32_t* vals_in,
                  std::uint32_t* vals_out, std::size_t n, int bits) {
    if (n == 0) return;
    if (bits == 0) {  // one cell: the order is kept
      copy(keys_out, keys_in, n * 4);
      copy(vals_out, vals_in, n * 4);
      return;
    }
    std::size_t need = 0;
    cuda_detail::check(cub::DeviceRadixSort::SortPairs(nullptr, need, keys_in, keys_out, vals_in, vals_out,
                                                       static_cast<int>(n), 0, bits, stream_),
                       "radix sort (size query)");
    if (need > sort_temp_bytes_) {
      release(sort_temp_);
      sort_temp_ = nullptr;
      sort_temp_ = alloc(need);
      sort_temp_bytes_ = need;
    }
    std::size_t have = sort_temp_bytes_;
    cuda_detail::check(cub::DeviceRadixSort::SortPairs(sort_temp_, have, keys_in, keys_out, vals_in, vals_out,
                                                       static_cast<int>(n), 0, bits, stream_),
                       "radix sort");
  }
  std::size_t bytes_in_use() const { return in_use_; }
  std::size_t sort_temp_bytes() const { return sort_temp_bytes_; }

 private:
  cudaStream_t stream_ = nullptr;
  cudaStream_t copy_stream_ = nullptr;  // asynchronous downloads
  cudaEvent_t ready_ = nullptr;
  std::vector<void*> pinned_;
  void* partial_ = nullptr;
  void* result_ = nullptr;
  void* sort_temp_ = nullptr;
  std::size_t sort_temp_bytes_ = 0;
  std::size_t in_use_ = 0;
  std::unordered_map<void*, std::size_t> sizes_;
};

}  // namespace varsph::exec
