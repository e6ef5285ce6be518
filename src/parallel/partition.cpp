#include "parallel/partition.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace varsph::parallel {

template <int D>
Partition<D>::Partition(const Coord& dims) : dims_(dims) {
  Node root;
  root.box.hi = dims;
  root.leaf = 0;
  nodes_.push_back(root);
  boxes_.push_back(root.box);
}

template <int D>
Partition<D> Partition<D>::build(Communicator& comm, const Coord& dims, std::span<const Coord> cells,
                                 std::span<const std::int32_t> weights) {
  const int P = comm.size();
  Partition part(dims);
  part.nodes_[0].r1 = P;
  part.nodes_[0].leaf = P == 1 ? 0 : -1;
  std::vector<int> node_of(cells.size(), 0);
  std::vector<int> frontier;
  if (P > 1) frontier.push_back(0);
  std::vector<int> slot;
  std::vector<std::int64_t> hist, offset;
  while (!frontier.empty()) {
    // one histogram per box and axis (every axis: the cut goes where the weight splits best), in one
    // allreduce per tree level
    offset.assign(frontier.size() * D + 1, 0);
    for (std::size_t k = 0; k < frontier.size(); ++k)
      for (int a = 0; a < D; ++a) {
        const CellBox<D>& b = part.nodes_[std::size_t(frontier[k])].box;
        offset[k * D + std::size_t(a) + 1] = offset[k * D + std::size_t(a)] + (b.hi[a] - b.lo[a]);
      }
    slot.assign(part.nodes_.size(), -1);
    for (std::size_t k = 0; k < frontier.size(); ++k) slot[std::size_t(frontier[k])] = int(k);
    hist.assign(std::size_t(offset.back()), 0);
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const int k = slot[std::size_t(node_of[i])];
      if (k < 0) continue;
      const CellBox<D>& b = part.nodes_[std::size_t(frontier[std::size_t(k)])].box;
      for (int a = 0; a < D; ++a)
        hist[std::size_t(offset[std::size_t(k) * D + std::size_t(a)] + cells[i][a] - b.lo[a])] += weights[i];
    }
    comm.sum(hist);  // integers: the same sums, hence the same cuts, on every rank
    std::vector<int> next;
    for (std::size_t k = 0; k < frontier.size(); ++k) {
      const int id = frontier[k];
      Node nd = part.nodes_[std::size_t(id)];
      const int n = nd.r1 - nd.r0, nl = n / 2;
      // per axis that can be cut with enough cells on both sides: the cell boundary c (cells [0, c)
      // left) whose left weight is closest to nl / n of the total, compared in integers (no rounding)
      int a_best = -1;
      std::int64_t best = 0;
      long double best_err = -1;
      std::array<std::int64_t, D> ext{};
      for (int a = 0; a < D; ++a) ext[a] = nd.box.hi[a] - nd.box.lo[a];
      std::array<int, D> order;
      for (int a = 0; a < D; ++a) order[a] = a;
      std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return ext[x] > ext[y]; });
      for (int a : order) {  // longest axis first: it wins ties (and takes the geometric cut without weight)
        const std::int64_t e = ext[a], other = nd.box.volume() / std::max<std::int64_t>(e, 1);
        const std::int64_t cmin = (nl + other - 1) / other, cmax = e - (n - nl + other - 1) / other;
        if (!(e >= 2 && cmin <= cmax && cmin >= 1 && cmax <= e - 1)) continue;
        const std::int64_t* h = hist.data() + offset[k * D + std::size_t(a)];
        std::int64_t total = 0;
        for (std::int64_t c = 0; c < e; ++c) total += h[c];
        if (total == 0) {  // no weight: the geometric share along the longest axis
          if (a_best < 0) {
            a_best = a;
            best = std::clamp<std::int64_t>((e * nl + n / 2) / n, cmin, cmax);
            best_err = 0;
          }
          break;
        }
        std::int64_t cum = 0;
        for (std::int64_t c = 0; c < cmin; ++c) cum += h[c];
        for (std::int64_t c = cmin; c <= cmax; ++c) {
          const long double d = (long double)cum * n - (long double)total * nl, err = d < 0 ? -d : d;
          if (best_err < 0 || err < best_err) {
            best_err = err;
            best = c;
            a_best = a;
          }
          cum += h[c];
        }
      }
      if (a_best < 0)
        throw std::invalid_argument("a box of " + std::to_string(nd.box.volume()) + " cells cannot be split among " +
                                    std::to_string(n) + " ranks: use fewer ranks or a larger domain");
      const int a = a_best;
      const std::int64_t lo = nd.box.lo[a];
      nd.axis = a;
      part.nodes_[std::size_t(id)].axis = a;
      Node left, right;
      left.box = right.box = nd.box;
      left.box.hi[a] = lo + best;
      right.box.lo[a] = lo + best;
      left.r0 = nd.r0;
      left.r1 = nd.r0 + nl;
      right.r0 = nd.r0 + nl;
      right.r1 = nd.r1;
      left.leaf = left.r1 - left.r0 == 1 ? left.r0 : -1;
      right.leaf = right.r1 - right.r0 == 1 ? right.r0 : -1;
      const int li = int(part.nodes_.size());
      part.nodes_.push_back(left);
      part.nodes_.push_back(right);
      Node& stored = part.nodes_[std::size_t(id)];
      stored.cut = lo + best;
      stored.left = li;
      stored.right = li + 1;
      if (left.leaf < 0) next.push_back(li);
      if (right.leaf < 0) next.push_back(li + 1);
    }
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const Node& nd = part.nodes_[std::size_t(node_of[i])];
      if (nd.left >= 0 && slot[std::size_t(node_of[i])] >= 0)
        node_of[i] = cells[i][nd.axis] < nd.cut ? nd.left : nd.right;
    }
    frontier = std::move(next);
  }
  part.boxes_.assign(std::size_t(P), CellBox<D>{});
  for (const Node& nd : part.nodes_)
    if (nd.leaf >= 0) part.boxes_[std::size_t(nd.leaf)] = nd.box;
  return part;
}

template class Partition<2>;
template class Partition<3>;

}  // namespace varsph::parallel
