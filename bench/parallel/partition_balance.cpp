// Where the partition's imbalance comes from (docs/parallel.md "Load balance"): the heaviest RCB box over
// the mean weight for a dam-break load (the fluid in the lower-left fifth of the grid, 3 particles of
// weight 4 per fluid cell, one of weight 1 per wall cell: tests/parallel/test_partition.cpp's cloud) at
// P ranks, as the grid is refined (more cells per rank at the same shape). If the imbalance falls toward
// 1 with refinement, cell granularity is its cause; if it stays, the cut rule is. One process plays P
// ranks (every reduction is the identity, exact). Prints a table; no timing.
#include <algorithm>
#include <array>
#include <cstdio>
#include <numeric>
#include <vector>

#include "parallel/all_in_one_communicator.hpp"
#include "parallel/partition.hpp"

using namespace varsph::parallel;

namespace {

template <int D>
void row(const std::array<std::int64_t, D>& base, int refine, int P) {
  std::array<std::int64_t, D> dims;
  for (int a = 0; a < D; ++a) dims[a] = base[a] * refine;
  std::vector<std::array<std::int64_t, D>> cells;
  std::vector<std::int32_t> w;
  std::array<std::int64_t, D> idx{};
  std::int64_t fluid_cells = 0;
  while (true) {
    bool fluid = idx[0] < dims[0] / 5;
    for (int a = 1; a < D; ++a) fluid = fluid && idx[a] < dims[a] / 2;
    bool wall = false;
    for (int a = 0; a < D; ++a) wall = wall || idx[a] == 0 || idx[a] == dims[a] - 1;
    fluid_cells += fluid;
    for (int k = 0; k < (fluid ? 3 : wall ? 1 : 0); ++k) {
      cells.push_back(idx);
      w.push_back(fluid ? 4 : 1);
    }
    int a = 0;
    while (a < D && ++idx[a] == dims[a]) idx[a++] = 0;
    if (a == D) break;
  }
  AllInOneCommunicator comm(P);
  const auto part = Partition<D>::build(comm, dims, cells, w);
  std::vector<double> load(std::size_t(P), 0.0);
  for (std::size_t i = 0; i < cells.size(); ++i) load[std::size_t(part.owner(cells[i]))] += w[i];
  const double mean = std::accumulate(load.begin(), load.end(), 0.0) / P;
  // ghosts: particles within 2 cells (the stencil of the grid's default subdivision) of another rank's box
  double ghosts = 0;
  for (std::size_t i = 0; i < cells.size(); ++i)
    for (int r = 0; r < P; ++r) {
      bool in = r != part.owner(cells[i]);
      for (int a = 0; a < D && in; ++a) in = cells[i][a] >= part.box(r).lo[a] - 2 && cells[i][a] < part.box(r).hi[a] + 2;
      ghosts += in;
    }
  std::printf("%dD %3d ranks  refine %d  grid", D, P, refine);
  for (int a = 0; a < D; ++a) std::printf(" %lld", (long long)dims[a]);
  std::printf("  fluid cells/rank %8.0f  heaviest/mean %.3f  ghosts/particles %.3f\n", double(fluid_cells) / P,
              *std::max_element(load.begin(), load.end()) / mean, ghosts / double(cells.size()));
}

}  // namespace

int main() {
  for (int P : {6, 8, 16, 32, 64})
    for (int r : {1, 2, 4, 8}) row<2>({120, 60}, r, P);
  for (int P : {6, 16, 32, 64})
    for (int r : {1, 2, 3, 6}) row<3>({60, 24, 24}, r, P);
  return 0;
}
