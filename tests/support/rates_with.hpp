#pragma once
// Rates for a simulation's physics with the pair sweep VARSPH_SIMD names (scalar, avx2, avx512), at the
// simulation's time: the vector and split sweeps are compared against these in their tests.
#include <cstdlib>
#include <memory>

#include "physics/rates.hpp"
#include "sim/simulation.hpp"

namespace varsph::test {

template <int D>
std::unique_ptr<physics::Rates<D>> rates_with(const Simulation<D>& sim, const char* isa) {
  setenv("VARSPH_SIMD", isa, 1);
  auto r = physics::make_rates<D>(sim.params());
  unsetenv("VARSPH_SIMD");
  r->set_time(sim.time());
  return r;
}

}  // namespace varsph::test
