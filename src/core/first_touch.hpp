#pragma once
// NUMA-aware first touch. Linux puts a page on the memory node of the thread that first writes it, and
// std::vector::resize writes every new element from the calling thread, so a large array would sit on
// one node and every other socket would read it remotely. first_touch_resize() reserves fresh storage,
// has each thread write (zero) the bytes of the elements it owns under the loops' static schedule -
// which places the pages - and only then resizes. Arrays big enough to matter come straight from mmap
// (untouched pages); small ones may reuse heap pages and keep their placement, which does not matter.
#include <cstddef>
#include <cstring>
#include <vector>

#include <omp.h>

#include "core/team.hpp"

namespace varsph {

// The same inside a step's parallel region (core/team.hpp): every thread of the team calls it.
template <class T>
void first_touch_resize_in_team(std::vector<T>& v, std::size_t n) {
  if (n <= v.capacity()) {
    team_single([&] { v.resize(n); });
    return;
  }
  std::vector<T> fresh;             // used on the thread that runs the single below
  std::vector<T>* shared = nullptr;  // that vector, broadcast to the team
  team_detail::TeamState* st = team_detail::tls_team;
#pragma omp single copyprivate(shared)
  {
    try {
      fresh.reserve(n);
      shared = &fresh;
    } catch (...) {
      st->error = std::current_exception();
    }
  }
  if (st->error) throw team_detail::Abort{};
  std::byte* raw = reinterpret_cast<std::byte*>(shared->data());
  const long nn = long(n), nt = omp_get_num_threads(), t = omp_get_thread_num();
  const long q = nn / nt, r = nn % nt;  // the partition of `#pragma omp for schedule(static)`
  const long lo = t * q + (t < r ? t : r), hi = lo + q + (t < r ? 1 : 0);
  if (hi > lo) std::memset(raw + std::size_t(lo) * sizeof(T), 0, std::size_t(hi - lo) * sizeof(T));
#pragma omp barrier
  team_single([&] {
    shared->insert(shared->end(), v.begin(), v.end());
    shared->resize(n);
    v.swap(*shared);
  });  // its barrier keeps `fresh` (now the old storage) alive until every thread is past the swap
}

template <class T>
void first_touch_resize(std::vector<T>& v, std::size_t n) {
  if (in_team()) return first_touch_resize_in_team(v, n);
  if (n <= v.capacity() || omp_get_max_threads() == 1) {
    v.resize(n);
    return;
  }
  std::vector<T> fresh;
  fresh.reserve(n);
  // the storage from the allocation function holds implicitly created objects: writing its bytes is defined
  std::byte* raw = reinterpret_cast<std::byte*>(fresh.data());
  const long nn = long(n);
#pragma omp parallel
  {
    // the partition of `#pragma omp for schedule(static)` over n iterations
    const long nt = omp_get_num_threads(), t = omp_get_thread_num();
    const long q = nn / nt, r = nn % nt;
    const long lo = t * q + (t < r ? t : r), hi = lo + q + (t < r ? 1 : 0);
    if (hi > lo) std::memset(raw + std::size_t(lo) * sizeof(T), 0, std::size_t(hi - lo) * sizeof(T));
  }
  fresh.insert(fresh.end(), v.begin(), v.end());
  fresh.resize(n);
  v.swap(fresh);
}

}  // namespace varsph
