#pragma once
// The host launch of the device loops (docs/gpu.md): runs the device backend's bodies (loop_bodies.hpp,
// step_bodies.hpp) on the CPU with the CUDA launch's indexing (a grid of blocks of kBlock threads,
// index = block * kBlock + thread), its two-pass block reductions and its stable LSD radix sort, in
// "device memory" that is host memory. Machines without a GPU (CI) test the backend through it
// (execution.device = "cuda_emulation"); it is not meant to be fast.
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <unordered_map>
#include <vector>

#include "exec/loop_bodies.hpp"

namespace varsph::exec {

class HostLaunch {
 public:
  static constexpr std::size_t kBlock = 256;        // threads per block, as the CUDA launch
  static constexpr std::size_t kReduceBlocks = 1024;  // most blocks of a reduction's first pass
  static const char* name() { return "cuda_emulation"; }

  HostLaunch() = default;
  HostLaunch(const HostLaunch&) = delete;
  HostLaunch& operator=(const HostLaunch&) = delete;
  ~HostLaunch() {
    for (auto& [p, n] : sizes_) std::free(p);
  }

  // --- memory ------------------------------------------------------------------------------------
  void* alloc(std::size_t bytes) {
    if (bytes == 0) return nullptr;
    void* p = std::malloc(bytes);
    if (!p) throw std::bad_alloc();
    sizes_[p] = bytes;
    in_use_ += bytes;
    return p;
  }
  void release(void* p) {
    if (!p) return;
    auto it = sizes_.find(p);
    if (it != sizes_.end()) {
      in_use_ -= it->second;
      sizes_.erase(it);
    }
    std::free(p);
  }
  std::size_t bytes_in_use() const { return in_use_; }
  void to_device(void* dst, const void* src, std::size_t bytes) { if (bytes) std::memcpy(dst, src, bytes); }
  void to_host(void* dst, const void* src, std::size_t bytes) { if (bytes) std::memcpy(dst, src, bytes); }
  void copy(void* dst, const void* src, std::size_t bytes) { if (bytes) std::memcpy(dst, src, bytes); }
  void synchronize() {}
  // device -> host copies that may overlap later loops (CUDA: a second stream); here they are done at once
  void to_host_async(void* dst, const void* src, std::size_t bytes) { to_host(dst, src, bytes); }
  void wait_host_async() {}
  void pin(void*, std::size_t) {}
  void unpin(void*) {}

  // --- loops ---------------------------------------------------------------------------------------
  template <class Body>
  void for_each(std::size_t n, const Body& body) {
    const long blocks = long((n + kBlock - 1) / kBlock);
#pragma omp parallel for schedule(static)
    for (long b = 0; b < blocks; ++b)
      for (std::size_t t = 0; t < kBlock; ++t) {
        const std::size_t i = std::size_t(b) * kBlock + t;
        if (i < n) body(i);
      }
  }

  // First pass: block b's thread t combines indices b kBlock + t + k (blocks kBlock), then the block's
  // tree; second pass: one block over the partials. Op: T, identity(), combine(a, b).
  template <class Op, class Body>
  typename Op::T reduce(std::size_t n, const Body& body) {
    using T = typename Op::T;
    const std::size_t blocks = std::min(kReduceBlocks, std::max<std::size_t>(1, (n + kBlock - 1) / kBlock));
    std::vector<T> partial(blocks), sh(kBlock);
    for (std::size_t b = 0; b < blocks; ++b) {
      for (std::size_t t = 0; t < kBlock; ++t) {
        T acc = Op::identity();
        for (std::size_t i = b * kBlock + t; i < n; i += blocks * kBlock) acc = Op::combine(acc, body(i));
        sh[t] = acc;
      }
      partial[b] = tree<Op>(sh);
    }
    for (std::size_t t = 0; t < kBlock; ++t) {
      T acc = Op::identity();
      for (std::size_t i = t; i < blocks; i += kBlock) acc = Op::combine(acc, partial[i]);
      sh[t] = acc;
    }
    return tree<Op>(sh);
  }

  // Stable LSD radix sort of (key, value) pairs on the low `bits` bits of the keys, 8 bits a pass
  // (the permutation cub::DeviceRadixSort gives: a stable sort by key is unique).
  void sort_pairs(const std::uint32_t* keys_in, std::uint32_t* keys_out, const std::uint32_t* vals_in,
                  std::uint32_t* vals_out, std::size_t n, int bits) {
    ka_.assign(keys_in, keys_in + n);
    va_.assign(vals_in, vals_in + n);
    kb_.resize(n);
    vb_.resize(n);
    for (int shift = 0; shift < bits; shift += 8) {
      std::size_t count[257] = {};
      for (std::size_t i = 0; i < n; ++i) ++count[((ka_[i] >> shift) & 0xffu) + 1];
      for (int d = 0; d < 256; ++d) count[d + 1] += count[d];
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t at = count[(ka_[i] >> shift) & 0xffu]++;
        kb_[at] = ka_[i];
        vb_[at] = va_[i];
      }
      ka_.swap(kb_);
      va_.swap(vb_);
    }
    std::memcpy(keys_out, ka_.data(), n * sizeof(std::uint32_t));
    std::memcpy(vals_out, va_.data(), n * sizeof(std::uint32_t));
  }

 private:
  template <class Op>
  static typename Op::T tree(std::vector<typename Op::T>& sh) {
    for (std::size_t s = kBlock / 2; s > 0; s /= 2)
      for (std::size_t t = 0; t < s; ++t) sh[t] = Op::combine(sh[t], sh[t + s]);
    return sh[0];
  }
  std::unordered_map<void*, std::size_t> sizes_;
  std::size_t in_use_ = 0;
  std::vector<std::uint32_t> ka_, kb_, va_, vb_;  // sort scratch, grown once
};

}  // namespace varsph::exec
