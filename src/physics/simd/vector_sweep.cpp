#include "physics/simd/vector_sweep.hpp"

#include <stdexcept>

namespace varsph::physics::simd {
namespace {

// Structure-of-arrays scratch of one thread: 6 candidate arrays and two lists of 5 arrays each.
struct ScratchStorage {
  std::uint32_t capacity = 0;
  std::vector<double> reals;
  std::vector<std::int32_t> ints;
  SweepScratch view{};
  void grow(std::uint32_t n) {
    capacity = std::max<std::uint32_t>(n, 2 * capacity);
    const std::size_t c = capacity;
    reals.assign(13 * c, 0.0);  // cx[3], cid, cwall; vec dx[3], r2; other dx[3], r2
    ints.assign(3 * c, 0);      // cj, vec.j, other.j
    double* r = reals.data();
    for (int a = 0; a < 3; ++a) view.cx[a] = r + a * c;
    view.cid = r + 3 * c;
    view.cwall = r + 4 * c;
    for (int a = 0; a < 3; ++a) view.vec.dx[a] = r + (5 + a) * c;
    view.vec.r2 = r + 8 * c;
    for (int a = 0; a < 3; ++a) view.other.dx[a] = r + (9 + a) * c;
    view.other.r2 = r + 12 * c;
    view.cj = ints.data();
    view.vec.j = ints.data() + c;
    view.other.j = ints.data() + 2 * c;
  }
};

}  // namespace

SweepScratch* thread_scratch(std::uint32_t candidates) {
  thread_local ScratchStorage s;
  if (candidates > s.capacity) s.grow(candidates);
  return &s.view;
}

void run_sweep(Isa isa, const SweepArgs& args) {
#if defined(VARSPH_SIMD_X86)
  if (isa == Isa::Avx512) return sweep_avx512(args);
  if (isa == Isa::Avx2) return sweep_avx2(args);
#endif
  throw std::logic_error("run_sweep: no vector sweep for this instruction set in this build");
}

}  // namespace varsph::physics::simd
