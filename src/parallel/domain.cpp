#include "parallel/domain.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <string>

#include "core/errors.hpp"

namespace varsph::parallel {
namespace {

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// dst[k] = src[rows[k]] for elements of B bytes (B known at compile time for the common sizes).
template <std::size_t B>
void gather_fixed(const std::byte* src, std::span<const std::uint32_t> rows, std::byte* dst) {
  const long n = long(rows.size());
#pragma omp parallel for schedule(static) if (n > 65536)
  for (long k = 0; k < n; ++k) std::memcpy(dst + std::size_t(k) * B, src + std::size_t(rows[std::size_t(k)]) * B, B);
}
void gather_bytes(const std::byte* src, std::size_t b, std::span<const std::uint32_t> rows, std::byte* dst) {
  switch (b) {
    case 4: return gather_fixed<4>(src, rows, dst);
    case 8: return gather_fixed<8>(src, rows, dst);
    case 12: return gather_fixed<12>(src, rows, dst);
    case 16: return gather_fixed<16>(src, rows, dst);
    case 24: return gather_fixed<24>(src, rows, dst);
    case 32: return gather_fixed<32>(src, rows, dst);
    default:
      for (std::size_t k = 0; k < rows.size(); ++k) std::memcpy(dst + k * b, src + std::size_t(rows[k]) * b, b);
  }
}

// Keeps rows[k] as row k of every field (rows may repeat none and may index past the new size).
void gather_store(ParticleStore& store, std::span<const std::uint32_t> rows, std::vector<std::byte>& scratch) {
  for (const auto& f : store.fields()) {
    const std::size_t b = f->bytes_per_particle();
    scratch.resize(rows.size() * b);
    gather_bytes(static_cast<const std::byte*>(f->raw()), b, rows, scratch.data());
    f->resize(rows.size());
    if (!rows.empty()) std::memcpy(f->raw(), scratch.data(), rows.size() * b);
  }
  store.resize(rows.size());
}

std::size_t row_bytes(std::span<FieldBase* const> fields) {
  std::size_t b = 0;
  for (const FieldBase* f : fields) b += f->bytes_per_particle();
  return b;
}

// Field-major packing: for each field, the rows' elements one after the other.
void pack(std::span<FieldBase* const> fields, std::span<const std::uint32_t> rows, std::byte* out) {
  for (const FieldBase* f : fields) {
    const std::size_t b = f->bytes_per_particle();
    gather_bytes(static_cast<const std::byte*>(f->raw()), b, rows, out);
    out += rows.size() * b;
  }
}
void unpack(std::span<FieldBase* const> fields, std::size_t first, std::size_t count, const std::byte* in) {
  for (FieldBase* f : fields) {
    const std::size_t b = f->bytes_per_particle();
    if (count) std::memcpy(static_cast<std::byte*>(f->raw()) + first * b, in, count * b);
    in += count * b;
  }
}

}  // namespace

template <int D>
Domain<D>::Domain(std::shared_ptr<Communicator> comm, DomainOptions options)
    : comm_(std::move(comm)), opt_(options) {
  if (const char* e = std::getenv("VARSPH_HALO_OVERLAP")) {
    const std::string want(e);
    if (want != "on" && want != "off") throw InputError("VARSPH_HALO_OVERLAP=" + want + ": expected on or off");
    opt_.overlap = want == "on";
  }
}

template <int D>
void Domain<D>::attach(ParticleStore& store, std::vector<std::string> halo_fields) {
  tag_ = &store.add<std::int64_t>("parallel_order_tag", {.exported = false, .checkpointed = false});
  kind_ = &store.get<std::int32_t>("kind");
  halo_names_ = std::move(halo_fields);
  owned_ = store.size();
  ghosts_ = 0;
}

template <int D>
void Domain<D>::adopt(ParticleStore& store, std::int64_t first_row) {
  owned_ = store.size();
  ghosts_ = 0;
  for (std::size_t i = 0; i < owned_; ++i) (*tag_)[i] = first_row + std::int64_t(i);
  repartition_pending_ = true;
}

template <int D>
void Domain<D>::compact_owned(ParticleStore& store, std::span<const std::uint32_t> kept) {
  if (!kept.empty() && kept.back() >= owned_) throw std::logic_error("Domain::compact_owned: not an owned row");
  store.compact(kept);
  owned_ = kept.size();
  ghosts_ = 0;
}

template <int D>
std::size_t Domain<D>::append_owned(ParticleStore& store, std::span<const std::uint32_t> src,
                                    std::span<const std::int64_t> order, std::int64_t tag_base) {
  if (src.size() != order.size()) throw std::logic_error("Domain::append_owned: one order per source row");
  for (const std::uint32_t i : src)
    if (i >= owned_) throw std::logic_error("Domain::append_owned: not an owned row");
  store.resize(owned_);  // ghosts dropped: the new rows follow the owned ones
  ghosts_ = 0;
  const std::size_t first = src.empty() ? owned_ : store.append_copies(src);
  for (std::size_t k = 0; k < src.size(); ++k) {
    if (k > 0 && order[k] <= order[k - 1]) throw std::logic_error("Domain::append_owned: order not ascending");
    // above every (cell << 32 | place) tag (cells < 2^32 - 1), in creation order
    (*tag_)[first + k] = std::int64_t((std::uint64_t(0xFFFFFFFFu) << 32) | std::uint64_t(tag_base + order[k]));
  }
  owned_ += src.size();
  return first;
}

template <int D>
typename Domain<D>::Coord Domain<D>::cell_of(const Vec<D>& x) const {
  Coord c;
  for (int a = 0; a < D; ++a) {
    // the serial grid's binning (NeighborGrid::coord_of): the same floating-point operations
    double f = std::floor(double(x[a] - min_[a]) / double(cell_[a]));
    if (!(f >= 0)) f = 0;  // below the domain (and NaN, which the health check reports)
    f = std::min(f, double(dims_[a] - 1));
    c[a] = std::int64_t(f);
  }
  return c;
}

template <int D>
std::int64_t Domain<D>::global_key(const Coord& c) const {
  std::int64_t k = 0;
  for (int a = D - 1; a >= 0; --a) k = k * dims_[a] + c[a];
  return k;
}

template <int D>
void Domain<D>::configure_from(const NeighborGrid<D>& grid) {
  if (grid.hashed())
    throw InputError("domain.neighbor_search = \"hash\" cannot be split among MPI ranks: give the domain bounds "
                     "and use the uniform grid");
  bool same = partitioned_;
  const auto& o = grid.options();
  for (int a = 0; a < D; ++a) {
    same = same && dims_[a] == grid.cells_per_axis()[a] && cell_[a] == grid.cell_size(a);
    dims_[a] = grid.cells_per_axis()[a];
    cell_[a] = grid.cell_size(a);
    min_[a] = o.min[a];
    periodic_[a] = o.periodic[a];
  }
  m_ = std::max(1, o.subdivision);
  if (!same) repartition_pending_ = true;
}

template <int D>
void Domain<D>::repartition(std::span<const Vec<D>> x, std::span<const std::int32_t> kind, std::size_t n) {
  std::vector<std::int32_t> w(n);
  for (std::size_t i = 0; i < n; ++i) w[i] = kind[i] == 0 ? opt_.fluid_weight : opt_.boundary_weight;
  try {
    partition_ = Partition<D>::build(*comm_, dims_, std::span<const Coord>(cells_.data(), n), w);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("domain decomposition into ") + std::to_string(comm_->size()) + " ranks: " + e.what());
  }
  (void)x;
  box_ = partition_.box(comm_->rank());
  partitioned_ = true;
  repartition_pending_ = false;
  ++stats_.repartitions;
  find_peers();
}

template <int D>
void Domain<D>::find_peers() {
  peers_.clear();
  const int me = comm_->rank();
  int n_images = 1;
  for (int a = 0; a < D; ++a) n_images *= 3;
  for (int q = 0; q < partition_.ranks(); ++q) {
    if (q == me) continue;
    const CellBox<D>& bq = partition_.box(q);
    Peer p;
    p.rank = q;
    for (int s = 0; s < n_images; ++s) {
      // q sees my cell c at c + k dims (k per periodic axis in -1..1): c in window_q - k dims
      CellBox<D> inter = box_;
      bool skip = false;
      int t = s;
      for (int a = 0; a < D; ++a) {
        const int k = t % 3 - 1;
        t /= 3;
        if (k != 0 && !periodic_[a]) {
          skip = true;
          break;
        }
        const std::int64_t lo = bq.lo[a] - m_ - k * dims_[a], hi = bq.hi[a] + m_ - k * dims_[a];
        inter.lo[a] = std::max(inter.lo[a], lo);
        inter.hi[a] = std::min(inter.hi[a], hi);
      }
      if (!skip && !inter.empty()) p.send_boxes.push_back(inter);
    }
    if (!p.send_boxes.empty()) peers_.push_back(std::move(p));
  }
}

template <int D>
void Domain<D>::rebin(ParticleStore& store, NeighborGrid<D>& grid, std::span<Field<Vec<D>>* const> position_like) {
  ++stats_.rebins;
  if (in_flight_) throw std::logic_error("Domain::rebin: a halo refresh is in flight");
  const double w0 = comm_->wait_seconds();
  configure_from(grid);
  store.resize(owned_);  // ghosts are rebuilt below
  ghosts_ = 0;
  auto& xf = store.get<Vec<D>>("position");
  {
    bool any_periodic = false;
    for (int a = 0; a < D; ++a) any_periodic |= periodic_[a];
    if (any_periodic) {  // as Simulation::sort_and_bin does in one process
      for (std::size_t i = 0; i < owned_; ++i) {
        const Vec<D> s = grid.wrap_shift(xf[i]);
        if (s.squaredNorm() > 0) {
          xf[i] += s;
          for (auto* f : position_like) f->data[i] += s;
        }
      }
    }
  }
  cells_.resize(owned_);
  {
    const long n = long(owned_);
    const Vec<D>* x = xf.data.data();
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) cells_[std::size_t(i)] = cell_of(x[i]);
  }
  if (repartition_pending_) repartition(xf.data, kind_->data, owned_);
  migrate(store, cells_);
  exchange_ghosts(store);
  build_topology(store.get<Vec<D>>("position").data, grid);
  stats_.rebin_wait_seconds += comm_->wait_seconds() - w0;
  if (opt_.overlap) {  // interior blocks: every neighbour range lies among the owned particles [0, owned)
    const auto& ranges = grid.ranges();
    const std::uint32_t owned = std::uint32_t(owned_);
    split_.build(grid, [&](const CellBlock& b) {
      for (std::uint32_t r = b.nbr_begin; r < b.nbr_end; ++r)
        if (ranges[r].end > owned) return false;
      return true;
    });
    stats_.interior_particles = std::int64_t(split_.picked_particles());
  }
}

template <int D>
void Domain<D>::migrate(ParticleStore& store, std::span<const Coord> cells) {
  const int P = comm_->size(), me = comm_->rank();
  const std::size_t n = owned_;
  out_rows_.resize(std::size_t(P));
  for (auto& r : out_rows_) r.clear();
  keep_.clear();
  bool off_peer = false;  // a destination that is not a peer (after a repartition, or a jump)
  std::vector<char> is_peer(std::size_t(P), 0);
  for (const Peer& p : peers_) is_peer[std::size_t(p.rank)] = 1;
  for (std::size_t i = 0; i < n; ++i) {
    const int q = P == 1 ? 0 : partition_.owner(cells[i]);
    if (q == me) {
      keep_.push_back(std::uint32_t(i));
    } else {
      out_rows_[std::size_t(q)].push_back(std::uint32_t(i));
      off_peer = off_peer || !is_peer[std::size_t(q)];
    }
  }
  std::vector<FieldBase*> all;
  for (const auto& f : store.fields()) all.push_back(f.get());
  const std::size_t B = row_bytes(all);
  // counts: from peers only, unless some rank sends beyond its peers (then from everybody)
  std::vector<std::int64_t> in_counts(std::size_t(P), 0);
  if (P > 1) {
    const bool global = comm_->max(off_peer ? 1.0 : 0.0) > 0;
    if (global) {
      std::vector<std::int64_t> c(static_cast<std::size_t>(P));
      for (int q = 0; q < P; ++q) c[std::size_t(q)] = std::int64_t(out_rows_[std::size_t(q)].size());
      in_counts = comm_->alltoall(c);
    } else {
      std::vector<std::int64_t> out_c(peers_.size()), in_c(peers_.size());
      out_msgs_.clear();
      in_msgs_.clear();
      for (std::size_t k = 0; k < peers_.size(); ++k) {
        out_c[k] = std::int64_t(out_rows_[std::size_t(peers_[k].rank)].size());
        out_msgs_.push_back({peers_[k].rank, reinterpret_cast<std::byte*>(&out_c[k]), sizeof(std::int64_t)});
        in_msgs_.push_back({peers_[k].rank, reinterpret_cast<std::byte*>(&in_c[k]), sizeof(std::int64_t)});
      }
      comm_->exchange(out_msgs_, in_msgs_);
      for (std::size_t k = 0; k < peers_.size(); ++k) in_counts[std::size_t(peers_[k].rank)] = in_c[k];
    }
  }
  // data, field-major per destination
  send_buf_.resize(std::size_t(P));
  recv_buf_.resize(std::size_t(P));
  out_msgs_.clear();
  in_msgs_.clear();
  std::size_t n_in = 0;
  for (int q = 0; q < P; ++q) {
    const auto& rows = out_rows_[std::size_t(q)];
    if (!rows.empty()) {
      auto& buf = send_buf_[std::size_t(q)];
      buf.resize(rows.size() * B);
      pack(all, rows, buf.data());
      out_msgs_.push_back({q, buf.data(), buf.size()});
      stats_.migrated += std::int64_t(rows.size());
    }
    if (in_counts[std::size_t(q)] > 0) {
      auto& buf = recv_buf_[std::size_t(q)];
      buf.resize(std::size_t(in_counts[std::size_t(q)]) * B);
      in_msgs_.push_back({q, buf.data(), buf.size()});
      n_in += std::size_t(in_counts[std::size_t(q)]);
    }
  }
  if (P > 1) comm_->exchange(out_msgs_, in_msgs_);
  // received particles after the old ones; runs of tag-sorted rows: the kept ones, then one per source
  store.resize(n + n_in);
  std::vector<std::size_t> run_starts;
  order_.assign(keep_.begin(), keep_.end());
  std::size_t at = n;
  for (int q = 0; q < P; ++q) {
    const std::size_t c = std::size_t(in_counts[std::size_t(q)]);
    if (c == 0) continue;
    unpack(all, at, c, recv_buf_[std::size_t(q)].data());
    run_starts.push_back(order_.size());
    for (std::size_t k = 0; k < c; ++k) order_.push_back(std::uint32_t(at + k));
    at += c;
  }
  order_owned(store, keep_.size(), run_starts);
}

template <int D>
void Domain<D>::order_owned(ParticleStore& store, std::size_t kept, const std::vector<std::size_t>& run_starts) {
  (void)kept;
  const std::int64_t* tag = tag_->data.data();
  // tags compare as unsigned: the cell key fills the upper 32 bits
  auto by_tag = [tag](std::uint32_t a, std::uint32_t b) {
    return std::uint64_t(tag[a]) < std::uint64_t(tag[b]);
  };
  // merge the tag-sorted runs into one tag-sorted sequence: the serial storage order before this sort
  for (std::size_t r = 0; r < run_starts.size(); ++r) {
    const std::size_t end = r + 1 < run_starts.size() ? run_starts[r + 1] : order_.size();
    std::inplace_merge(order_.begin(), order_.begin() + std::ptrdiff_t(run_starts[r]),
                       order_.begin() + std::ptrdiff_t(end), by_tag);
  }
  // stable counting sort by cell within the box: cell order, ties in serial order
  const auto& xs = store.get<Vec<D>>("position").data;
  const std::size_t n = order_.size();
  std::array<std::int64_t, D> ext;
  std::int64_t vol = 1;
  for (int a = 0; a < D; ++a) {
    ext[a] = box_.hi[a] - box_.lo[a];
    vol *= ext[a];
  }
  keys_.resize(n);
  cells_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Coord c = cell_of(xs[order_[k]]);
    cells_[k] = c;
    std::int64_t key = 0;
    for (int a = D - 1; a >= 0; --a) key = key * ext[a] + std::clamp<std::int64_t>(c[a] - box_.lo[a], 0, ext[a] - 1);
    keys_[k] = key;
  }
  counts_.assign(std::size_t(vol) + 1, 0);
  for (std::size_t k = 0; k < n; ++k) ++counts_[std::size_t(keys_[k]) + 1];
  for (std::int64_t c = 0; c < vol; ++c) counts_[std::size_t(c) + 1] += counts_[std::size_t(c)];
  std::vector<std::uint32_t> rows(n);
  std::vector<Coord> sorted_cells(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t slot = counts_[std::size_t(keys_[k])]++;
    rows[slot] = order_[k];
    sorted_cells[slot] = cells_[k];
  }
  gather_store(store, rows, gather_scratch_);
  owned_ = n;
  // new tags: (global cell << 32) | place in the cell
  std::int64_t* t = tag_->data.data();
  std::size_t first = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0 && sorted_cells[k] != sorted_cells[k - 1]) first = k;
    t[k] = std::int64_t((std::uint64_t(global_key(sorted_cells[k])) << 32) | std::uint64_t(k - first));
  }
  cells_ = std::move(sorted_cells);
}

template <int D>
void Domain<D>::exchange_ghosts(ParticleStore& store) {
  halo_fields_.clear();
  for (const auto& name : halo_names_)
    if (FieldBase* f = store.find(name)) halo_fields_.push_back(f);
  const std::size_t B = row_bytes(halo_fields_);
  // what each peer needs: my cells inside its window, walked cell by cell in storage order
  for (Peer& p : peers_) {
    p.send.clear();
    std::size_t b = 0;
    while (b < owned_) {
      std::size_t e = b + 1;
      while (e < owned_ && cells_[e] == cells_[b]) ++e;
      bool in = false;
      for (const auto& box : p.send_boxes) in = in || box.contains(cells_[b]);
      if (in)
        for (std::size_t i = b; i < e; ++i) p.send.push_back(std::uint32_t(i));
      b = e;
    }
  }
  std::vector<std::int64_t> out_c(peers_.size()), in_c(peers_.size());
  out_msgs_.clear();
  in_msgs_.clear();
  for (std::size_t k = 0; k < peers_.size(); ++k) {
    out_c[k] = std::int64_t(peers_[k].send.size());
    out_msgs_.push_back({peers_[k].rank, reinterpret_cast<std::byte*>(&out_c[k]), sizeof(std::int64_t)});
    in_msgs_.push_back({peers_[k].rank, reinterpret_cast<std::byte*>(&in_c[k]), sizeof(std::int64_t)});
  }
  if (!peers_.empty()) comm_->exchange(out_msgs_, in_msgs_);
  send_buf_.resize(std::max(send_buf_.size(), peers_.size()));
  recv_buf_.resize(std::max(recv_buf_.size(), peers_.size()));
  out_msgs_.clear();
  in_msgs_.clear();
  std::size_t total = 0;
  for (std::size_t k = 0; k < peers_.size(); ++k) {
    Peer& p = peers_[k];
    p.recv_count = std::size_t(in_c[k]);
    p.recv_offset = total;
    total += p.recv_count;
    auto& sb = send_buf_[k];
    sb.resize(p.send.size() * B);
    pack(halo_fields_, p.send, sb.data());
    if (!sb.empty()) out_msgs_.push_back({p.rank, sb.data(), sb.size()});
    stats_.halo_bytes_sent += std::int64_t(sb.size());
    auto& rb = recv_buf_[k];
    rb.resize(p.recv_count * B);
    if (!rb.empty()) in_msgs_.push_back({p.rank, rb.data(), rb.size()});
  }
  if (!peers_.empty()) comm_->exchange(out_msgs_, in_msgs_);
  store.resize(owned_ + total);
  for (std::size_t k = 0; k < peers_.size(); ++k)
    unpack(halo_fields_, owned_ + peers_[k].recv_offset, peers_[k].recv_count, recv_buf_[k].data());
  ghosts_ = total;
}

template <int D>
void Domain<D>::build_topology(std::span<const Vec<D>> x, NeighborGrid<D>& grid) {
  // window: my box and m cells around it, in unwrapped cell coordinates
  std::array<std::int64_t, D> wlo, wext;
  std::int64_t wvol = 1;
  for (int a = 0; a < D; ++a) {
    wlo[a] = box_.lo[a] - m_;
    wext[a] = box_.hi[a] - box_.lo[a] + 2 * m_;
    wvol *= wext[a];
  }
  window_.assign(std::size_t(wvol), {0u, 0u});
  auto window_index = [&](const Coord& u) {
    std::int64_t k = 0;
    for (int a = D - 1; a >= 0; --a) k = k * wext[a] + (u[a] - wlo[a]);
    return std::size_t(k);
  };
  // every image of cell c inside the window gets the range [b, e)
  auto place = [&](const Coord& c, std::uint32_t b, std::uint32_t e) {
    std::array<std::int64_t, D> opts[3];
    std::array<int, D> n_opt{};
    for (int a = 0; a < D; ++a) {
      for (int k = -1; k <= 1; ++k) {
        if (k != 0 && !periodic_[a]) continue;
        const std::int64_t u = c[a] + k * dims_[a];
        if (u >= wlo[a] && u < wlo[a] + wext[a]) opts[n_opt[a]++][a] = u;
      }
      if (n_opt[a] == 0) return;
    }
    std::array<int, D> idx{};
    while (true) {
      Coord u;
      for (int a = 0; a < D; ++a) u[a] = opts[idx[a]][a];
      window_[window_index(u)] = {b, e};
      int a = 0;
      while (a < D && ++idx[a] == n_opt[a]) idx[a++] = 0;
      if (a == D) break;
    }
  };
  const std::size_t n_all = owned_ + ghosts_;
  std::vector<Coord> ghost_cells(ghosts_);
  for (std::size_t i = 0; i < ghosts_; ++i) ghost_cells[i] = cell_of(x[owned_ + i]);
  auto cell_at = [&](std::size_t i) -> const Coord& { return i < owned_ ? cells_[i] : ghost_cells[i - owned_]; };
  blocks_.clear();
  for (std::size_t b = 0; b < n_all;) {
    std::size_t e = b + 1;
    // runs never cross from owned into ghost rows, nor between two peers' blocks
    while (e < n_all && e != owned_ && cell_at(e) == cell_at(b)) ++e;
    place(cell_at(b), std::uint32_t(b), std::uint32_t(e));
    if (b < owned_) blocks_.push_back({std::uint32_t(b), std::uint32_t(e), 0, 0});
    b = e;
  }
  // neighbour ranges of each block in the serial grid's order: rows over axes 1..D-1 (axis 1 fastest),
  // then x offsets -m..m; periodic images carry the shift NeighborGrid::shift_id gives them
  ranges_.clear();
  const int w = 2 * m_ + 1;
  const int n_rows = D == 2 ? w : w * w;
  for (auto& blk : blocks_) {
    const Coord c = cells_[blk.begin];
    blk.nbr_begin = std::uint32_t(ranges_.size());
    NeighborRange pending{0, 0, 0};
    bool have = false;
    auto push = [&](std::uint32_t b, std::uint32_t e, std::uint32_t shift) {
      if (b == e) return;
      if (have && pending.end == b && pending.shift == shift) {
        pending.end = e;
      } else {
        if (have) ranges_.push_back(pending);
        pending = {b, e, shift};
        have = true;
      }
    };
    for (int row = 0; row < n_rows; ++row) {
      Coord u = c;
      std::array<int, D> wrap{};
      bool valid = true;
      int t = row;
      for (int a = 1; a < D; ++a) {
        const int d = t % w - m_;
        t /= w;
        u[a] = c[a] + d;
        if (u[a] < 0 || u[a] >= dims_[a]) {
          if (!periodic_[a]) {
            valid = false;
            break;
          }
          wrap[a] = u[a] < 0 ? -1 : 1;
        }
      }
      if (!valid) continue;
      // the row's x offsets are consecutive window cells: its index and the shift of axes 1.. once per row
      u[0] = c[0];
      const std::size_t row_index = window_index(u);
      std::uint32_t row_shift = 0, mul = 3;
      for (int a = 1; a < D; ++a) {
        row_shift += std::uint32_t(wrap[a] + 1) * mul;
        mul *= 3;
      }
      for (int dx = -m_; dx <= m_; ++dx) {
        const std::int64_t x = c[0] + dx;
        std::uint32_t w0 = 1;  // wrap[0] + 1
        if (x < 0 || x >= dims_[0]) {
          if (!periodic_[0]) continue;
          w0 = x < 0 ? 0 : 2;
        }
        const auto& r = window_[std::size_t(std::ptrdiff_t(row_index) + dx)];
        push(r[0], r[1], row_shift + w0);
      }
    }
    if (have) ranges_.push_back(pending);
    blk.nbr_end = std::uint32_t(ranges_.size());
  }
  grid.set_topology(blocks_, ranges_, wlo, wext, window_);
}

template <int D>
void Domain<D>::begin_refresh(std::span<const HaloArray> arrays) {
  if (in_flight_) throw std::logic_error("halo refresh: begun while another is in flight");
  if (peers_.empty()) return;
  ++stats_.refreshes;
  std::size_t B = 0;
  for (const auto& a : arrays) {
    if (a.count < owned_ + ghosts_) throw std::logic_error("halo refresh: an array shorter than owned + ghost particles");
    B += a.bytes;
  }
  pending_.assign(arrays.begin(), arrays.end());
  out_msgs_.clear();
  in_msgs_.clear();
  for (std::size_t k = 0; k < peers_.size(); ++k) {
    const Peer& p = peers_[k];
    auto& sb = send_buf_[k];
    sb.resize(p.send.size() * B);
    std::byte* o = sb.data();
    for (const auto& a : arrays) {
      gather_bytes(static_cast<const std::byte*>(a.data), a.bytes, p.send, o);
      o += p.send.size() * a.bytes;
    }
    if (!sb.empty()) out_msgs_.push_back({p.rank, sb.data(), sb.size()});
    stats_.halo_bytes_sent += std::int64_t(sb.size());
    auto& rb = recv_buf_[k];
    rb.resize(p.recv_count * B);
    if (!rb.empty()) in_msgs_.push_back({p.rank, rb.data(), rb.size()});
  }
  const double w0 = comm_->wait_seconds();
  comm_->begin_exchange(out_msgs_, in_msgs_);
  stats_.refresh_wait_seconds += comm_->wait_seconds() - w0;
  in_flight_ = true;
}

template <int D>
void Domain<D>::finish_refresh() {
  if (!in_flight_) return;
  in_flight_ = false;
  const double w0 = comm_->wait_seconds();
  comm_->finish_exchange();
  stats_.refresh_wait_seconds += comm_->wait_seconds() - w0;
  for (std::size_t k = 0; k < peers_.size(); ++k) {
    const Peer& p = peers_[k];
    const std::byte* in = recv_buf_[k].data();
    for (const auto& a : pending_) {
      if (p.recv_count)
        std::memcpy(static_cast<std::byte*>(a.data) + (owned_ + p.recv_offset) * a.bytes, in, p.recv_count * a.bytes);
      in += p.recv_count * a.bytes;
    }
  }
}

template <int D>
void Domain<D>::step_begin() {
  step_t0_ = now_seconds();
  wait_t0_ = comm_->wait_seconds();
}

template <int D>
void Domain<D>::step_end(long step) {
  const double busy = (now_seconds() - step_t0_) - (comm_->wait_seconds() - wait_t0_);
  busy_since_check_ += busy;
  busy_since_report_ += busy;
  if (opt_.force_every > 0 && step % opt_.force_every == 0) repartition_pending_ = true;
  if (opt_.check_every > 0 && step % opt_.check_every == 0 && comm_->size() > 1) {
    // the gathered array is the same on every rank, so is the decision
    const auto all = comm_->allgather(busy_since_check_);
    busy_since_check_ = 0;
    const double mx = *std::max_element(all.begin(), all.end());
    const double mean = std::accumulate(all.begin(), all.end(), 0.0) / double(all.size());
    if (opt_.weights_by_cost) refit_weights(all);
    if (mean > 0 && mx / mean > opt_.threshold) repartition_pending_ = true;
  }
}

template <int D>
void Domain<D>::refit_weights(std::span<const double> busy) {
  std::int64_t fluid = 0;
  for (std::size_t i = 0; i < owned_; ++i) fluid += kind_->data[i] == 0;
  const auto f = comm_->allgather(double(fluid));
  const auto w = comm_->allgather(double(std::int64_t(owned_) - fluid));
  cost_fit_.add(busy, f, w);
  if (const auto bw = cost_fit_.boundary_weight()) {  // the same on every rank: same values, same arithmetic
    opt_.fluid_weight = CostFit::kFluidWeight;
    opt_.boundary_weight = *bw;
    ++stats_.weight_fits;
  }
}

template <int D>
double Domain<D>::imbalance_since_last_report() {
  const auto all = comm_->allgather(busy_since_report_);
  busy_since_report_ = 0;
  const double mx = *std::max_element(all.begin(), all.end());
  const double mean = std::accumulate(all.begin(), all.end(), 0.0) / double(all.size());
  return mean > 0 ? mx / mean : 1.0;
}

template class Domain<2>;
template class Domain<3>;

}  // namespace varsph::parallel
