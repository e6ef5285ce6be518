// Particle shifting (physics.shifting, src/physics/shifting.hpp): a disordered lattice relaxes toward a
// uniform one, a uniform lattice is not shifted, only positions change (velocities and momentum are
// untouched), free-surface particles stay put in "zero" mode, it works through every explicit integrator,
// it is thread-count independent, and bad keys are rejected with file and key named.
#include <omp.h>

#include <cstring>

#include "core/errors.hpp"
#include "toolbox_support.hpp"

using namespace varsph;
using namespace varsph::toolbox_test;

namespace {

constexpr double kDx = 0.05;

// Periodic n x n lattice (spacing kDx, box n kDx), Wendland C2 h = 1.3 dx, summation density, translating
// at (U, 0) so that D = A h |v| dt > 0 while the pair forces of a uniform lattice vanish.
json periodic_lattice(int n, double U, const std::string& integrator = "verlet") {
  const double L = n * kDx;
  return {{"name", "shift_lattice"},
          {"setup", "paper"}, {"dimension", 2},
          {"domain", {{"min", {0.0, 0.0}}, {"max", {L, L}}, {"periodic", {true, true}}}},
          {"particles", {{"spacing", kDx}}},
          {"kernel", {{"type", "wendland_c2"}, {"h_over_dx", 1.3}}},
          {"fluid", {{"rho0", 1000.0}, {"c0", 10.0}}},
          {"bodies", {{{"kind", "fluid"}, {"shape", "box"}, {"min", {0.0, 0.0}}, {"max", {L, L}},
                       {"velocity", {U, 0.0}}}}},
          {"physics", {{"density", "summation"}, {"shifting", json::object()}}},
          {"integrator", {{"type", integrator}, {"cfl", 0.2}}},
          {"time", {{"end", 1.0}}}};
}

void perturb(Simulation<2>& sim, double xstd, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, 1);
  auto& f = sim.fields();
  for (std::size_t i = 0; i < sim.size(); ++i)
    if (f.kind[i] == 0)
      for (int a = 0; a < 2; ++a) f.x[i][a] += Real(xstd * g(rng));
  sim.sort_and_bin();
}

// Relative spread std/mean of the number density sum_j W_ij (self term included) over fluid particles,
// brute force with the minimum image in a periodic box of side L (L = 0: not periodic).
double number_density_spread(const Simulation<2>& sim, double L) {
  const auto& s = sim.scene();
  kernels::AnyKernel<2> W(s.kernel, s.h, s.kernel_l);
  const auto& f = sim.fields();
  double sum = 0, sum2 = 0;
  int n = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.kind[i] != 0) continue;
    double nd = 0;
    for (std::size_t j = 0; j < sim.size(); ++j) {
      Vec<2> r = f.x[i] - f.x[j];
      if (L > 0)
        for (int a = 0; a < 2; ++a) r[a] -= Real(L * std::round(double(r[a]) / L));
      const double d = r.norm();
      if (d < W.support()) nd += W(Real(d)).w;
    }
    sum += nd;
    sum2 += nd * nd;
    ++n;
  }
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, sum2 / n - mean * mean)) / mean;
}

std::vector<Vec<2>> shifts(const Simulation<2>& sim) {
  std::vector<Vec<2>> dr(sim.size(), Vec<2>::Zero());
  sim.rates().shifting(sim.grid(), sim.current_view(), Real(sim.dt()), dr.data());
  return dr;
}

std::string error_of(json j) {
  try {
    scene::parse_scene_json(j, "bad_shift.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Shifting, UniformPeriodicLatticeIsNotShifted) {
  json j = periodic_lattice(20, 1.0);
  Simulation<2> sim(parse(j));
  ASSERT_TRUE(sim.shifting_enabled());
  double max_uniform = 0;
  for (const auto& d : shifts(sim)) max_uniform = std::max(max_uniform, double(d.norm()));
  // the same lattice with 5 % dx noise is shifted: the measure can tell
  perturb(sim, 0.05 * kDx, 1);
  double max_noisy = 0;
  for (const auto& d : shifts(sim)) max_noisy = std::max(max_noisy, double(d.norm()));
  std::printf("max |dr| / dx: uniform lattice %.3g, 5%% noise %.3g\n", max_uniform / kDx, max_noisy / kDx);
  EXPECT_LT(max_uniform, 1e-12 * kDx);
  EXPECT_GT(max_noisy, 1e-4 * kDx);
}

TEST(Shifting, PerturbedLatticeRelaxesTowardUniform) {
  // shifting alone (no time stepping): dr applied 30 times at D = A h |v| dt = 0.1 h^2 (U = 1, A = 2)
  json j = periodic_lattice(20, 1.0);
  Simulation<2> sim(parse(j));
  perturb(sim, 0.1 * kDx, 2);
  const double L = 20 * kDx;
  const double before = number_density_spread(sim, L);
  sim.set_dt(0.05 * sim.scene().h);
  for (int k = 0; k < 30; ++k) {
    sim.apply_shifting();
    sim.sort_and_bin();
  }
  const double after = number_density_spread(sim, L);
  std::printf("number-density spread std/mean: %.4f before, %.4f after 30 shifts\n", before, after);
  EXPECT_LT(after, 0.3 * before);
}

TEST(Shifting, ChangesPositionsOnlyNotVelocitiesOrMomentum) {
  json j = periodic_lattice(16, 1.0);
  Simulation<2> sim(parse(j));
  perturb(sim, 0.1 * kDx, 3);
  std::mt19937 rng(4);
  std::normal_distribution<double> g(0, 0.3);
  auto& f = sim.fields();
  for (std::size_t i = 0; i < sim.size(); ++i) f.v[i] += Vec<2>(Real(g(rng)), Real(g(rng)));
  const auto x0 = f.x.data;
  const auto v0 = f.v.data;
  Vec<2> p0 = Vec<2>::Zero();
  for (std::size_t i = 0; i < sim.size(); ++i) p0 += f.mass[i] * f.v[i];
  sim.apply_shifting();
  double moved = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) moved = std::max(moved, double((f.x[i] - x0[i]).norm()));
  Vec<2> p1 = Vec<2>::Zero();
  for (std::size_t i = 0; i < sim.size(); ++i) p1 += f.mass[i] * f.v[i];
  EXPECT_GT(moved, 1e-4 * kDx);  // it did shift
  EXPECT_EQ(std::memcmp(v0.data(), f.v.data.data(), v0.size() * sizeof(Vec<2>)), 0);
  EXPECT_EQ(p0, p1);
}

TEST(Shifting, FreeSurfaceParticlesAreNotShiftedInZeroMode) {
  // a free block of fluid (no walls, not periodic), 10 % dx noise, translating: in "none" mode the edge
  // particles are shifted (outward: kernel deficiency); in "zero" mode (div r ~ 1.25 < 1.5) they stay
  const int n = 16;
  for (const std::string mode : {"none", "zero"}) {
    json j = periodic_lattice(n, 1.0);
    j["domain"] = {{"min", {-1.0, -1.0}}, {"max", {2.0, 2.0}}};
    j["physics"]["shifting"] = {{"free_surface", mode}};
    Simulation<2> sim(parse(j));
    perturb(sim, 0.1 * kDx, 5);
    const auto dr = shifts(sim);
    const auto& f = sim.fields();
    double edge_max = 0, bulk_max = 0;
    for (std::size_t i = 0; i < sim.size(); ++i) {
      const double e = std::min({double(f.x[i][0]), double(f.x[i][1]), n * kDx - double(f.x[i][0]),
                                 n * kDx - double(f.x[i][1])});
      const double d = dr[i].norm() / kDx;
      if (e < 0.6 * kDx) edge_max = std::max(edge_max, d);
      if (e > 4 * kDx) bulk_max = std::max(bulk_max, d);
    }
    std::printf("free_surface %s: max |dr|/dx on the outer row %.3g, in the bulk %.3g\n", mode.c_str(), edge_max,
                bulk_max);
    EXPECT_GT(bulk_max, 1e-4);
    if (mode == "zero") EXPECT_EQ(edge_max, 0.0);
    else EXPECT_GT(edge_max, 0.01);  // shifted (outward: the kernel support is truncated there)
  }
}

TEST(Shifting, TangentialModeKeepsOnlyTheSurfaceParallelShiftNearTheSurface) {
  // Sun et al. 2017 eq. 25: in the band below the free surface only (I - n n) dr is kept, so particles are
  // not pushed through the surface (the outward drift of "none"), yet they still spread along it. Second
  // row of a free noisy block (away from corners): normal (outward) and tangential parts, zero vs tangential.
  const int n = 16;
  double normal_of[2] = {0, 0}, tangential_of[2] = {0, 0};
  int k = 0;
  for (const std::string mode : {"zero", "tangential"}) {
    json j = periodic_lattice(n, 1.0);
    j["domain"] = {{"min", {-1.0, -1.0}}, {"max", {2.0, 2.0}}};
    j["physics"]["shifting"] = {{"free_surface", mode}};
    if (mode == "tangential") j["physics"]["shifting"]["near_surface_threshold"] = 1.99;
    Simulation<2> sim(parse(j));
    perturb(sim, 0.1 * kDx, 5);
    const auto dr = shifts(sim);
    const auto& f = sim.fields();
    int count = 0;
    for (std::size_t i = 0; i < sim.size(); ++i) {
      const double y = double(f.x[i][1]), x = double(f.x[i][0]);
      // second row from the top edge y = n dx, 3 dx from the side edges
      if (n * kDx - y < 1.0 * kDx || n * kDx - y > 2.0 * kDx || x < 3 * kDx || x > (n - 3) * kDx) continue;
      normal_of[k] += double(dr[i][1]);  // signed: the outward drift toward the surface
      tangential_of[k] += std::abs(double(dr[i][0]));
      ++count;
    }
    normal_of[k] = std::abs(normal_of[k]) / (count * kDx);
    tangential_of[k] /= count * kDx;
    std::printf("free_surface %s, second row: |mean dr_normal|/dx %.3g, |dr_tangential|/dx %.3g (%d particles)\n",
                mode.c_str(), normal_of[k], tangential_of[k], count);
    ++k;
  }
  EXPECT_LT(normal_of[1], 0.3 * normal_of[0]) << "no net drift through the surface";
  EXPECT_GT(tangential_of[1], 0.3 * tangential_of[0]) << "the tangential part stays";
  // the band bound is checked: above the threshold, below the dimension
  json bad = periodic_lattice(n, 1.0);
  bad["physics"]["shifting"] = {{"free_surface", "tangential"}, {"near_surface_threshold", 1.2}};
  EXPECT_NE(error_of(bad).find("near_surface_threshold"), std::string::npos) << error_of(bad);
}

TEST(Shifting, EveryExplicitIntegratorAppliesIt) {
  // 40 steps of a noisy translating lattice: the number-density spread ends lower with shifting than without
  for (const std::string integ : {"verlet", "symplectic_euler", "predictor_corrector", "rk4", "verlet_dsph"}) {
    double spread[2];
    for (int k = 0; k < 2; ++k) {
      json j = periodic_lattice(16, 1.0, integ);
      if (integ == "verlet_dsph") j["physics"]["density"] = "continuity";  // its only density mode
      j["physics"]["shifting"] = {{"coefficient", 4.0}};
      if (k == 0) j["physics"].erase("shifting");
      Simulation<2> sim(parse(j));
      perturb(sim, 0.1 * kDx, 6);
      sim.rates().summation_density(sim.grid(), sim.current_view(), sim.fields().rho.data.data());
      sim.update_pressure();
      for (int s = 0; s < 40; ++s) {
        sim.advance();
        ASSERT_EQ(check_health(sim), "") << integ << " step " << s;
      }
      spread[k] = number_density_spread(sim, 16 * kDx);
    }
    std::printf("%s: number-density spread after 40 steps %.4f without, %.4f with shifting\n", integ.c_str(),
                spread[0], spread[1]);
    EXPECT_LT(spread[1], 0.8 * spread[0]) << integ;
  }
}

TEST(Shifting, ThreadCountIndependent) {
  json j = periodic_lattice(16, 1.0);
  j["physics"]["shifting"] = {{"velocity", "max"}};
  std::vector<Vec<2>> x[2];
  for (int k = 0; k < 2; ++k) {
    omp_set_num_threads(k + 1);
    Simulation<2> sim(parse(j));
    perturb(sim, 0.1 * kDx, 7);
    for (int s = 0; s < 30; ++s) sim.advance();
    x[k] = sim.fields().x.data;
  }
  omp_set_num_threads(1);
  EXPECT_EQ(std::memcmp(x[0].data(), x[1].data(), x[0].size() * sizeof(Vec<2>)), 0);
}

TEST(Shifting, BadKeysAreRejectedWithFileAndKey) {
  const auto expect_error = [](json j, const std::string& key) {
    const std::string e = error_of(j);
    EXPECT_NE(e.find("bad_shift.json"), std::string::npos) << e;
    EXPECT_NE(e.find(key), std::string::npos) << "expected '" << key << "' in: " << e;
  };
  json j = periodic_lattice(8, 1.0);
  ASSERT_EQ(error_of(j), "");
  j["physics"]["shifting"] = 2.0;
  expect_error(j, "physics.shifting");
  j["physics"]["shifting"] = {{"velocity", "fast"}};
  expect_error(j, "physics.shifting.velocity");
  j["physics"]["shifting"] = {{"coefficient", -1.0}};
  expect_error(j, "physics.shifting.coefficient");
  j["physics"]["shifting"] = {{"free_surface", "normal"}};
  expect_error(j, "physics.shifting.free_surface");
  j["physics"]["shifting"] = {{"max_shift", 2.0}};
  expect_error(j, "physics.shifting.max_shift");
  j["physics"]["shifting"] = {{"tensile_n", 0}};
  expect_error(j, "physics.shifting.tensile_n");
  j["physics"]["shifting"] = {{"typo", 1}};
  expect_error(j, "physics.shifting.typo");
  j["physics"]["shifting"] = json::object();
  j["integrator"]["type"] = "variational";
  expect_error(j, "physics.shifting");
}
