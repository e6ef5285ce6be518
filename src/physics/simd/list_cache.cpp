#include "physics/simd/list_cache.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <string>

#include "core/errors.hpp"
#include "core/team.hpp"

namespace varsph::physics::simd {
namespace {
std::atomic<std::uint64_t> reuses{0};
}  // namespace

std::uint64_t ListCache::total_reuses() { return reuses.load(std::memory_order_relaxed); }

ListCache::ListCache() {
  if (const char* e = std::getenv("VARSPH_NEIGHBOUR_LISTS")) {
    const std::string want(e);
    if (want != "reuse" && want != "rebuild")
      throw InputError("VARSPH_NEIGHBOUR_LISTS=" + want + ": expected reuse or rebuild");
    enabled_ = want == "reuse";
  }
}

bool ListCache::same_key(const SweepArgs& A, const void* grid, std::uint64_t generation, std::size_t n) const {
  return grid == grid_ && generation == generation_ && n == n_ && A.rc2 == rc2_ && A.dim == dim_ &&
         std::memcmp(A.x, x_.data(), n * std::size_t(A.dim) * sizeof(double)) == 0 &&
         std::memcmp(A.kind, kind_.data(), n * sizeof(std::int32_t)) == 0;
}

// Upper bound of the stored lists: every particle of a block keeps at most its block's candidates (+ padding).
bool ListCache::within_budget(const SweepArgs& A, int lanes) const {
  const std::size_t per_entry = sizeof(std::int32_t) + std::size_t(A.dim + 1) * sizeof(double);
  std::size_t entries = 0;
  for (long b = 0; b < A.n_blocks; ++b) {
    const std::uint32_t* blk = A.blocks + 4 * std::size_t(b);
    std::size_t cand = 0;
    for (std::uint32_t r = blk[2]; r < blk[3]; ++r) cand += A.ranges[3 * std::size_t(r) + 1] - A.ranges[3 * std::size_t(r)];
    entries += std::size_t(blk[1] - blk[0]) * (cand + std::size_t(lanes));
    if (entries * per_entry > kBudgetBytes) return false;
  }
  return true;
}

void ListCache::prepare(SweepArgs& A, const void* grid, std::uint64_t generation, std::size_t n, int lanes) {
  team_single([&] { mode_ = decide(A, grid, generation, n, lanes); });  // once per team (core/team.hpp)
  A.list_mode = mode_;
  if (mode_ == 2) {
    A.lists = this;
    A.load_lists = &ListCache::load;
  } else if (mode_ == 1) {
    A.lists = this;
    A.store_lists = &ListCache::store;
  }
}

int ListCache::decide(const SweepArgs& A, const void* grid, std::uint64_t generation, std::size_t n, int lanes) {
  if (!enabled_ || A.walls_only) return 0;
  if (same_key(A, grid, generation, n)) {
    reuse_seen_ = true;
    if (stored_ && lanes == lanes_) {
      reuses.fetch_add(1, std::memory_order_relaxed);
      return 2;
    }
  } else {
    stored_ = false;
    if (!within_budget(A, lanes)) {  // too large to keep: rebuild in every pass, keep no key either
      x_ = {};
      kind_ = {};
      grid_ = nullptr;
      return 0;
    }
    grid_ = grid;
    generation_ = generation;
    n_ = n;
    rc2_ = A.rc2;
    dim_ = A.dim;
    x_.assign(A.x, A.x + n * std::size_t(A.dim));
    kind_.assign(A.kind, A.kind + n);
    if (!reuse_seen_) return 0;  // no scheme so far has come back to a configuration: storing would not pay
  }
  // store this pass's lists
  lanes_ = lanes;
  rec_.resize(n);
  arenas_.resize(std::size_t(std::max(1, omp_get_max_threads())));
  for (Arena& a : arenas_) a.ni = a.nr = 0;
  stored_ = true;
  return 1;
}

void ListCache::store(void* self, std::uint32_t i, const NeighbourList& vec, const NeighbourList& other) {
  ListCache& c = *static_cast<ListCache*>(self);
  const int D = c.dim_;
  Arena& a = c.arenas_[std::size_t(omp_get_thread_num())];
  const std::size_t nvp = vec.n + std::size_t(c.lanes_);  // the vector list with its padding lanes
  const std::size_t ni = nvp + other.n, nr = std::size_t(D + 1) * ni;
  if (a.ni + ni > a.ints.size()) a.ints.resize(std::max(2 * a.ints.size(), a.ni + ni));
  if (a.nr + nr > a.reals.size()) a.reals.resize(std::max(2 * a.reals.size(), a.nr + nr));
  c.rec_[i] = {std::uint32_t(omp_get_thread_num()), vec.n, other.n, a.ni, a.nr};
  std::int32_t* ip = a.ints.data() + a.ni;
  double* rp = a.reals.data() + a.nr;
  std::copy_n(vec.j, nvp, ip);
  std::copy_n(other.j, other.n, ip + nvp);
  for (int d = 0; d <= D; ++d) {  // per list: dx[0..D-1], r2
    const double* sv = d < D ? vec.dx[d] : vec.r2;
    const double* so = d < D ? other.dx[d] : other.r2;
    std::copy_n(sv, nvp, rp + std::size_t(d) * nvp);
    std::copy_n(so, other.n, rp + (D + 1) * nvp + std::size_t(d) * other.n);
  }
  a.ni += ni;
  a.nr += nr;
}

void ListCache::load(const void* self, std::uint32_t i, NeighbourList& vec, NeighbourList& other) {
  const ListCache& c = *static_cast<const ListCache*>(self);
  const int D = c.dim_;
  const Record& r = c.rec_[i];
  const Arena& a = c.arenas_[r.thread];
  const std::size_t nvp = r.nv + std::size_t(c.lanes_);
  // the sweep only reads the lists: the const_cast gives them NeighbourList's (writable) pointer type
  std::int32_t* ip = const_cast<std::int32_t*>(a.ints.data()) + r.ints;
  double* rp = const_cast<double*>(a.reals.data()) + r.reals;
  vec.j = ip;
  other.j = ip + nvp;
  for (int d = 0; d < D; ++d) {
    vec.dx[d] = rp + std::size_t(d) * nvp;
    other.dx[d] = rp + (D + 1) * nvp + std::size_t(d) * r.no;
  }
  vec.r2 = rp + std::size_t(D) * nvp;
  other.r2 = rp + (D + 1) * nvp + std::size_t(D) * r.no;
  vec.n = r.nv;
  other.n = r.no;
}

}  // namespace varsph::physics::simd
