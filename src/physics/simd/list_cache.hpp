#pragma once
// Neighbour lists kept from one pass of the vectorised sweep to the next over the same configuration.
// The explicit schemes evaluate the continuity equation at q_{k+1} and, one step later, the forces at the
// same q_{k+1} (verlet, symplectic_euler); the variational integrator evaluates both at each midpoint. Each
// pass used to redo the candidate test and compaction (37 % of the default scene's instructions). The
// cache keys a configuration by the neighbour grid (object and generation), the support radius and a
// byte copy of the positions and kinds the pass reads: lists are reused only for a bitwise identical
// configuration, so results are bitwise those of the rebuild. It starts storing lists only once two
// consecutive passes have met the same configuration (a scheme with one fused pass per step pays only
// the key comparison), and stays off when the lists could exceed kBudgetBytes (large cases: memory).
// VARSPH_NEIGHBOUR_LISTS=rebuild turns it off (A/B benchmarks, tests).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "physics/simd/sweep_args.hpp"

namespace varsph::physics::simd {

class ListCache {
 public:
  static constexpr std::size_t kBudgetBytes = std::size_t(64) << 20;

  ListCache();  // reads VARSPH_NEIGHBOUR_LISTS (reuse | rebuild; anything else: InputError)

  // Sets A.list_mode (and the cache's callbacks) for the pass A describes: 2 when this configuration's
  // lists are stored, 1 to store them during the pass, 0 otherwise. n: particles of A.x and A.kind;
  // lanes: the vector width of the sweep that will run (its list padding). Inside a step's parallel region
  // every thread calls it: one decides (team_single), each sets its own copy of A.
  void prepare(SweepArgs& A, const void* grid, std::uint64_t generation, std::size_t n, int lanes);

  bool enabled() const { return enabled_; }
  // passes, over every cache of the process, that took their lists from a cache (tests, benchmarks)
  static std::uint64_t total_reuses();

 private:
  struct Record {
    std::uint32_t thread, nv, no;
    std::size_t ints, reals;  // offsets of the particle's lists in its thread's arena
  };
  struct Arena {
    std::vector<std::int32_t> ints;
    std::vector<double> reals;
    std::size_t ni = 0, nr = 0;  // used
  };
  static void store(void* self, std::uint32_t i, const NeighbourList& vec, const NeighbourList& other);
  static void load(const void* self, std::uint32_t i, NeighbourList& vec, NeighbourList& other);
  int decide(const SweepArgs& A, const void* grid, std::uint64_t generation, std::size_t n, int lanes);
  bool same_key(const SweepArgs& A, const void* grid, std::uint64_t generation, std::size_t n) const;
  bool within_budget(const SweepArgs& A, int lanes) const;

  bool enabled_ = true;
  int mode_ = 0;             // the last decision (SweepArgs::list_mode)
  bool reuse_seen_ = false;  // two consecutive passes met the same configuration
  bool stored_ = false;      // the arenas hold the keyed configuration's lists
  // key of the last configuration
  const void* grid_ = nullptr;
  std::uint64_t generation_ = 0;
  std::size_t n_ = 0;
  double rc2_ = 0;
  std::vector<double> x_;
  std::vector<std::int32_t> kind_;
  // the lists
  int dim_ = 0, lanes_ = 0;
  std::vector<Record> rec_;
  std::vector<Arena> arenas_;  // one per thread (no locks while storing)
};

}  // namespace varsph::physics::simd
