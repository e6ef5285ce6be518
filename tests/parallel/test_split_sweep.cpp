// A pass run as two sweeps over complementary sets of the grid's blocks (parallel/block_split.hpp) equals
// the one sweep over all blocks bit for bit, on one process: what lets a distributed run sweep its
// interior blocks while the halo refresh is in flight (parallel/halo_rates.hpp) and still give the
// serial numbers. Every pass HaloRates splits, with the scalar and the vectorised sweep, for the wall
// models and optional terms of the scenes; and Rates::splits_by_blocks() refuses the scenes whose passes
// are not block-local (damping, Antuono's delta-SPH), for which a split is shown to change the result.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "parallel/block_split.hpp"
#include "scene/json_reader.hpp"
#include "scene/scene.hpp"
#include "sim/simulation.hpp"
#include "rates_with.hpp"
#include "test_support.hpp"

using namespace varsph;
using varsph::test::rates_with;

namespace {

// the paper's 2D dam break after some steps (moving fluid, densities off rho0), with scene changes
std::unique_ptr<Simulation<2>> dam_break(const std::vector<std::string>& sets, int steps = 20) {
  const auto file = test::source_dir() / "pipelines" / "dam_break_2d_paper.json";
  nlohmann::json j = scene::read_json_file(file);
  auto sim = std::make_unique<Simulation<2>>(scene::parse_scene_json(j, file, sets));
  for (int k = 0; k < steps; ++k) sim->advance();
  return sim;
}

// Outputs of one pass: every slot starts at the same sentinel, so slots a sweep leaves alone must match too.
template <int D>
struct Out {
  std::vector<Real> s1, s2;
  std::vector<Vec<D>> v1;
  explicit Out(std::size_t n) : s1(n, Real(-7)), s2(n, Real(-7)), v1(n, Vec<D>::Constant(Real(-7))) {}
  bool operator==(const Out& o) const {
    return std::memcmp(s1.data(), o.s1.data(), s1.size() * sizeof(Real)) == 0 &&
           std::memcmp(s2.data(), o.s2.data(), s2.size() * sizeof(Real)) == 0 &&
           std::memcmp(v1.data(), o.v1.data(), v1.size() * sizeof(Vec<D>)) == 0;
  }
};

// A pass: rates, grid, view, outputs.
template <int D>
using Pass = std::function<void(const physics::Rates<D>&, const NeighborGrid<D>&, const physics::ParticleView<D>&,
                                Out<D>&)>;

template <int D>
std::vector<std::pair<std::string, Pass<D>>> passes(const Simulation<D>& sim) {
  std::vector<std::pair<std::string, Pass<D>>> p;
  p.emplace_back("fused", [](auto& r, auto& g, auto& s, Out<D>& o) {
    r.density_rate_and_acceleration(g, s, o.s1.data(), o.v1.data());
  });
  p.emplace_back("density_rate", [](auto& r, auto& g, auto& s, Out<D>& o) { r.density_rate(g, s, o.s1.data()); });
  p.emplace_back("acceleration", [](auto& r, auto& g, auto& s, Out<D>& o) { r.acceleration(g, s, o.v1.data()); });
  p.emplace_back("summation_density",
                 [](auto& r, auto& g, auto& s, Out<D>& o) { r.summation_density(g, s, o.s1.data()); });
  if (sim.rates().xsph_enabled())
    p.emplace_back("xsph", [](auto& r, auto& g, auto& s, Out<D>& o) { r.xsph(g, s, o.v1.data()); });
  const auto geo = sim.wall_geometry();
  p.emplace_back("update_walls", [geo](auto& r, auto& g, auto& s, Out<D>& o) {
    r.update_walls(g, s, geo, o.s1.data(), o.s2.data(), o.v1.data());
  });
  return p;
}

// Three ways to split the blocks: a cut in space (as between two ranks), every third block, and
// everything in one part (the other empty).
template <int D>
std::vector<std::pair<std::string, std::function<bool(const CellBlock&)>>> picks(const Simulation<D>& sim) {
  const auto x = sim.current_view().x;
  return {{"x < 0.07 m", [x](const CellBlock& b) { return x[b.begin][0] < Real(0.07); }},
          {"every third block", [](const CellBlock& b) { return (b.begin / 7) % 3 == 0; }},
          {"all", [](const CellBlock&) { return true; }}};
}

template <int D>
void expect_split_equals_whole(const Simulation<D>& sim, const std::string& what) {
  const std::size_t n = sim.size();
  const auto view = sim.current_view();
  parallel::BlockSplit<D> split;
  for (const char* isa : {"scalar", "auto"}) {
    const auto rates = rates_with(sim, isa);
    ASSERT_TRUE(rates->splits_by_blocks()) << what;
    for (const auto& [pick_name, pick] : picks(sim)) {
      split.build(sim.grid(), pick);
      ASSERT_TRUE(split.made_from(sim.grid()));
      const std::size_t picked = split.picked_particles();
      if (pick_name != "all") {
        EXPECT_GT(picked, n / 10) << what << ", " << pick_name;  // both parts hold particles
        EXPECT_LT(picked, n - n / 10) << what << ", " << pick_name;
      } else {
        EXPECT_EQ(picked, n);
      }
      for (const auto& [pass_name, pass] : passes(sim)) {
        Out<D> whole(n), parts(n);
        pass(*rates, sim.grid(), view, whole);
        pass(*rates, split.part(0), view, parts);
        pass(*rates, split.part(1), view, parts);
        EXPECT_TRUE(whole == parts) << what << ", " << isa << " sweep, " << pass_name << ", split " << pick_name;
      }
    }
  }
}

}  // namespace

TEST(SplitSweep, RepulsiveWallsArtificialViscosityEqualsOneSweepBitwise) {  // the paper's scene
  expect_split_equals_whole(*dam_break({}), "repulsive + AV");
}

TEST(SplitSweep, DynamicWallsFourtakasDiffusionEqualsOneSweepBitwise) {  // the fused pass with wall densities
  expect_split_equals_whole(
      *dam_break({"boundary.model=\"dynamic\"", "physics.density_diffusion={\"type\": \"fourtakas\", \"delta\": 0.1}",
                  "integrator.type=\"verlet_dsph\""}),
      "dynamic + AV + Fourtakas");
}

TEST(SplitSweep, DummyWallsXsphArtificialStressEqualsOneSweepBitwise) {  // wall update, XSPH, a second sweep
  expect_split_equals_whole(
      *dam_break({"boundary.model=\"dummy_adami\"", "physics.xsph={}", "physics.tensile_instability={}"}),
      "dummy walls + XSPH + artificial stress");
}

// Damping subtracts mu v once per particle over all particles: split in two it would act twice.
// Antuono's delta-SPH reads the density gradients of the neighbours, computed by a sweep of the same call.
TEST(SplitSweep, PassesThatAreNotBlockLocalAreNotSplit) {
  const auto damped = dam_break({"physics.damping={\"mu\": 2, \"until\": 1}"}, 2);
  const auto antuono = dam_break({"physics.density_diffusion={\"type\": \"antuono\", \"delta\": 0.1}"}, 2);
  for (const auto* sim : {damped.get(), antuono.get()}) {
    EXPECT_FALSE(rates_with(*sim, "auto")->splits_by_blocks());
    EXPECT_FALSE(sim->rates().splits_by_blocks());
    // and a split does change their result (fresh rates each: no scratch left by the other): the refusal is needed
    parallel::BlockSplit<2> split;
    split.build(sim->grid(), [&](const CellBlock& b) { return sim->current_view().x[b.begin][0] < Real(0.07); });
    Out<2> whole(sim->size()), parts(sim->size());
    const auto view = sim->current_view();
    rates_with(*sim, "auto")->density_rate_and_acceleration(sim->grid(), view, whole.s1.data(), whole.v1.data());
    const auto r = rates_with(*sim, "auto");
    r->density_rate_and_acceleration(split.part(0), view, parts.s1.data(), parts.v1.data());
    r->density_rate_and_acceleration(split.part(1), view, parts.s1.data(), parts.v1.data());
    EXPECT_FALSE(whole == parts);
  }
  // past the damping window the damped scene's passes are block-local again
  auto r = rates_with(*damped, "auto");
  r->set_time(2.0);
  EXPECT_TRUE(r->splits_by_blocks());
}
