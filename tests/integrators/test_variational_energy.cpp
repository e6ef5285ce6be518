// Energy behaviour with summation density (the discrete Lagrangian of seed eq. 19): over 10^4 steps in a
// periodic box without viscosity, |E - E0| / K0 stays below 1e-3 and does not grow (max over the last
// 1000 steps <= 2 x max over the first 1000), for the variational scheme (alpha 0.5, 0.25) and Verlet.
// E_k = (K(v_{k-1/2}) + K(v_{k+1/2})) / 2 + sum m pi(rho(q_k)), rho by summation at q_k.
// The random velocities on a lattice first relax (kinetic energy spreads into acoustic modes, which
// changes the size of the O(dt^2) energy oscillation), so E0 and K0 are taken after 2000 warm-up steps.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdlib>

#include "physics/pair_loop.hpp"
#include "sim/diagnostics.hpp"
#include "test_support.hpp"
#include "variational_cases.hpp"

using namespace varsph;

namespace {

double kinetic(const Simulation<2>& sim) {
  double k = 0;
  for (std::size_t i = 0; i < sim.size(); ++i)
    k += 0.5 * double(sim.fields().mass[i]) * double(sim.fields().v[i].squaredNorm());
  return k;
}

double internal(const Simulation<2>& sim, std::vector<Real>& rho) {
  rho.resize(sim.size());
  sim.rates().summation_density(sim.grid(), sim.current_view(), rho.data());
  double u = 0;
  for (std::size_t i = 0; i < sim.size(); ++i)
    u += double(sim.fields().mass[i]) * tait_internal_energy(rho[i], sim.scene().rho0, double(sim.eos().B));
  return u;
}

class EnergyByScheme : public ::testing::TestWithParam<double> {};

TEST_P(EnergyByScheme, SummationDensityEnergyErrorIsSmallAndDoesNotGrow) {
  omp_set_num_threads(1);
  const double alpha = GetParam();
  const int steps = 10000;
  const char* kern = std::getenv("VARSPH_ENERGY_KERNEL");
  const char* dtenv = std::getenv("VARSPH_ENERGY_DT");
  auto j = test::lattice_scene(12, 0.5, true, alpha, alpha == 1 ? "verlet" : "variational", "summation",
                               dtenv ? std::atof(dtenv) : 1e-4);
  j["kernel"] = {{"type", kern ? kern : "wendland_c2"}};
  Simulation<2> sim(test::make_scene(j));
  for (int k = 0; k < 2000; ++k) sim.advance();  // warm-up
  std::vector<Real> rho;
  double K0 = 0, E0 = 0, first = 0, last = 0, worst = 0;
  for (int k = 0; k < steps; ++k) {
    const double U = internal(sim, rho), Km = kinetic(sim);
    sim.advance();
    const double E = 0.5 * (Km + kinetic(sim)) + U;
    if (k == 0) {
      K0 = 0.5 * (Km + kinetic(sim));
      E0 = E;
    }
    const double err = std::abs(E - E0) / K0;
    worst = std::max(worst, err);
    if (k < 1000) first = std::max(first, err);
    if (k >= steps - 1000) last = std::max(last, err);
  }
  std::printf("alpha %.2f: max |E - E0| / K0 = %.3g; first 1000 steps %.3g, last 1000 steps %.3g\n", alpha, worst,
              first, last);
  EXPECT_LT(worst, 1e-3);
  EXPECT_LE(last, 2 * first);
}

INSTANTIATE_TEST_SUITE_P(Schemes, EnergyByScheme, ::testing::Values(0.5, 0.25, 1.0));

}  // namespace
