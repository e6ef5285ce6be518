#pragma once
// Domain decomposition: the layer between the particle store and the neighbour search.
//
// Each rank owns the particles in its box of cells of the global neighbour grid (partition.hpp) and
// keeps them first in its store, [0, owned()); copies of the particles of other ranks within the
// stencil of its cells (the support radius plus the grid's skin: two cells of (support + skin) / 2)
// follow as ghosts, [owned(), owned() + ghosts()). rebin() replaces the serial sort: it migrates
// particles that left the box, orders the owned ones, receives the ghosts and builds the neighbour
// grid's blocks (owned cells only) and ranges (owned and ghost cells, periodic images by shift). Physics
// passes then run on owned particles and read ghosts as neighbours; refresh() copies the owners'
// current values of the arrays a pass reads (positions of a midpoint configuration, velocities,
// densities, pressures) into the ghosts before every pass (halo_rates.hpp does it for every pass).
//
// Same numbers as one process, bit for bit: the pair loop sums each particle's neighbours cell by cell
// in stencil order and, within a cell, in storage order. The serial program's storage order within a
// cell is the order of the previous sort (a stable counting sort), so every particle carries an order
// tag (its cell and place in that cell at the last sort) and rebin() orders owned particles by (cell,
// tag): the serial order. Ghosts arrive from their single owner in that order, and their ranges are
// visited with the same periodic shifts as in the serial grid. Each particle therefore sees the same
// neighbours in the same order with the same arithmetic on any number of ranks.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/particle_store.hpp"
#include "neighbors/neighbor_grid.hpp"
#include "parallel/block_split.hpp"
#include "parallel/cost_fit.hpp"
#include "parallel/communicator.hpp"
#include "parallel/partition.hpp"

namespace varsph::parallel {

// One array refreshed in the ghosts: `count` elements of `bytes` each (owned then ghosts).
struct HaloArray {
  void* data;
  std::size_t bytes;
  std::size_t count;
};

struct DomainOptions {
  // particle weights of the partition (integers: exact sums on every rank)
  std::int32_t fluid_weight = 4;
  std::int32_t boundary_weight = 1;
  // dynamic load balancing: every `check_every` steps the slowest rank's busy time over the mean;
  // above `threshold` the next rebin() repartitions (0 steps: never)
  double threshold = 1.15;
  long check_every = 50;
  long force_every = 0;  // repartition every this many steps whatever the imbalance (tests)
  // sweep the interior blocks (no ghost in their stencil) while a halo refresh is in flight
  // (halo_rates.hpp); VARSPH_HALO_OVERLAP=off turns it off (A/B benchmarks)
  bool overlap = true;
  // parallel.weights.mode = "cost": the boundary weight is refitted from the ranks' busy times at every
  // balance check (cost_fit.hpp); "count" keeps fluid_weight and boundary_weight
  bool weights_by_cost = false;
};

// Counters for reports and benchmarks.
struct DomainStats {
  std::int64_t rebins = 0, repartitions = 0, migrated = 0;
  std::int64_t halo_bytes_sent = 0;     // ghost rebuilds and refreshes, this rank, since construction
  std::int64_t refreshes = 0;
  std::int64_t overlapped_refreshes = 0;  // refreshes with the interior sweep between post and wait
  // seconds inside communication calls (waiting included): halo refreshes (post + wait), and rebin()
  // (migration, ghost rebuild, the partition's reductions)
  double refresh_wait_seconds = 0, rebin_wait_seconds = 0;
  std::int64_t interior_particles = 0;  // owned particles whose stencil holds no ghost, at the last rebin
  std::int64_t weight_fits = 0;         // balance checks that refitted the weights from cost
};

template <int D>
class Domain {
 public:
  using Coord = std::array<std::int64_t, D>;
  Domain(std::shared_ptr<Communicator> comm, DomainOptions options);

  Communicator& comm() { return *comm_; }
  const std::shared_ptr<Communicator>& comm_ptr() const { return comm_; }
  std::size_t owned() const { return owned_; }
  // True when x lies in a cell of this rank's box (the rank that computes a point query: probes).
  bool owns(const Vec<D>& x) const { return box_.contains(cell_of(x)); }
  std::size_t ghosts() const { return ghosts_; }
  const Partition<D>& partition() const { return partition_; }
  const DomainStats& stats() const { return stats_; }
  const DomainOptions& options() const { return opt_; }

  // Registers the order tag in the store; `halo_fields` names the fields ghosts carry at a rebuild
  // (those neighbours read; absent names are skipped). Call once, after the fields exist.
  void attach(ParticleStore& store, std::vector<std::string> halo_fields);
  // This rank keeps rows [first, first + n) of a particle list whose global row numbers are the order
  // tags (construction: rows in id order; restart: rows of the checkpoint). The store must hold
  // exactly those n rows; the next rebin() partitions from scratch.
  void adopt(ParticleStore& store, std::int64_t first_row);
  // The store holds n owned rows whose order tags were put back with them (a state snapshot restored);
  // the next rebin() partitions from scratch.
  void restore_owned(std::size_t n) {
    owned_ = n;
    ghosts_ = 0;
    repartition_pending_ = true;
  }
  // Keeps the owned rows `kept` (strictly ascending; their order tags stay) and drops every ghost: particle
  // removal (health.*). The caller then calls rebin() on every rank, which rebuilds the ghosts.
  void compact_owned(ParticleStore& store, std::span<const std::uint32_t> kept);
  // Drops every ghost and appends copies of the owned rows `src` (every field) as new owned rows; their order
  // tags put them after every existing particle, in the order `order` (ascending: the new particles' places
  // among all created this step on all ranks), as one process appends created particles at the end of its
  // store before its next sort (open boundaries). Returns the first new row. The caller then calls rebin()
  // on every rank. `tag_base` is added to the order in the tags (a second batch of the same step, after the first).
  std::size_t append_owned(ParticleStore& store, std::span<const std::uint32_t> src, std::span<const std::int64_t> order,
                           std::int64_t tag_base = 0);
  // The order tag of owned row i (its cell and place at the last rebin: the serial storage order).
  std::int64_t order_tag(std::size_t i) const { return (*tag_)[i]; }

  // Collective. Wraps periodic positions (and the position-like fields), migrates, orders, exchanges
  // ghosts and writes the grid's blocks and ranges. `grid` must be a configured uniform grid over the
  // global domain; a change of its cells (a new skin) repartitions.
  void rebin(ParticleStore& store, NeighborGrid<D>& grid, std::span<Field<Vec<D>>* const> position_like);
  // Collective. Owners' values of the arrays into the ghost slots (one message per peer).
  void refresh(std::span<const HaloArray> arrays) {
    begin_refresh(arrays);
    finish_refresh();
  }
  // refresh() in two halves: begin packs the owners' values and posts the messages, finish waits and
  // writes the ghost slots. Between them the owned values may be read, not written, and the ghost
  // slots are neither read nor written (they hold the previous values until finish).
  void begin_refresh(std::span<const HaloArray> arrays);
  void finish_refresh();
  // The grid's blocks split into interior (part 0: no ghost in the stencil) and boundary (part 1) ones,
  // made at the last rebin(); null when `grid` is not the grid rebin() built or overlap is off.
  const BlockSplit<D>* split_for(const NeighborGrid<D>& grid) const {
    return opt_.overlap && split_.made_from(grid) ? &split_ : nullptr;
  }
  void count_overlapped_refresh() { ++stats_.overlapped_refreshes; }

  // Load balance: the caller brackets each step; every check_every steps the busy times are compared
  // (collective) and a repartition is scheduled for the next rebin() when they differ too much.
  void step_begin();
  void step_end(long step);
  // Collective: slowest rank's busy time over the mean since the previous call (1 on one rank).
  double imbalance_since_last_report();
  // Collective: requests a partition from scratch at the next rebin().
  void request_repartition() { repartition_pending_ = true; }

  // Global cell of a position (the serial grid's binning, particles outside a bounded domain clamped
  // to the border cell).
  Coord cell_of(const Vec<D>& x) const;

 private:
  struct Peer {
    int rank;
    std::vector<CellBox<D>> send_boxes;  // my cells that fall in its window (with periodic images)
    std::vector<std::uint32_t> send;     // my owned particles it needs, in storage order
    std::size_t recv_count = 0, recv_offset = 0;  // its particles in my ghost slots
  };
  void configure_from(const NeighborGrid<D>& grid);
  void repartition(std::span<const Vec<D>> x, std::span<const std::int32_t> kind, std::size_t n);
  void refit_weights(std::span<const double> busy);  // collective (weights_by_cost)
  void find_peers();
  void migrate(ParticleStore& store, std::span<const Coord> cells);
  void order_owned(ParticleStore& store, std::size_t kept, const std::vector<std::size_t>& run_starts);
  void exchange_ghosts(ParticleStore& store);
  void build_topology(std::span<const Vec<D>> x, NeighborGrid<D>& grid);
  std::int64_t global_key(const Coord& c) const;

  std::shared_ptr<Communicator> comm_;
  DomainOptions opt_;
  Partition<D> partition_;
  bool partitioned_ = false, repartition_pending_ = true;
  // the grid the partition was made for
  Coord dims_{};
  std::array<Real, D> cell_{}, min_{};
  std::array<bool, D> periodic_{};
  int m_ = 2;  // stencil half-width in cells
  CellBox<D> box_{};

  Field<std::int64_t>* tag_ = nullptr;  // (cell << 32 | place in cell) at the last sort
  Field<std::int32_t>* kind_ = nullptr;
  std::vector<std::string> halo_names_;
  std::vector<FieldBase*> halo_fields_;
  std::size_t owned_ = 0, ghosts_ = 0;
  std::vector<Peer> peers_;
  DomainStats stats_;

  // scratch, reused between rebins (grows once)
  std::vector<Coord> cells_;
  std::vector<std::uint32_t> order_, keep_, counts_;
  std::vector<std::int64_t> keys_;
  std::vector<std::vector<std::uint32_t>> out_rows_;
  std::vector<std::vector<std::byte>> send_buf_, recv_buf_;
  std::vector<std::byte> gather_scratch_;
  std::vector<Message> out_msgs_, in_msgs_;
  std::vector<HaloArray> pending_;  // arrays of the refresh in flight
  bool in_flight_ = false;
  double refresh_wait_t0_ = 0;
  BlockSplit<D> split_;
  std::vector<CellBlock> blocks_;
  std::vector<NeighborRange> ranges_;
  std::vector<std::array<std::uint32_t, 2>> window_;  // (begin, end) of every cell of box +- m

  // busy-time bookkeeping (load balance and the imbalance column)
  double step_t0_ = 0, wait_t0_ = 0;
  double busy_since_check_ = 0, busy_since_report_ = 0;
  CostFit cost_fit_;  // weights_by_cost: the costs per particle kind fitted so far
};

}  // namespace varsph::parallel
