// Probes: validation messages, pressure / water height / front values on a hydrostatic column, the
// force on a boundary body balancing the fluid's pair forces, and probes.csv from the binary.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "../support/real_tolerance.hpp"
#include "core/errors.hpp"
#include "results_scenes.hpp"
#include "scene/scene.hpp"
#include "sim/probes.hpp"
#include "sim/simulation.hpp"
#include "test_support.hpp"

using namespace varsph;

namespace {

scene::Scene tiny(const std::vector<std::string>& overrides = {}) {
  return scene::parse_scene_json(test::tiny_dam_break(), "tiny.json", overrides);
}

std::string error_of(const std::vector<std::string>& overrides) {
  try {
    Probes<2> p(tiny(overrides));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Probes, ValidationNamesTheProbeKey) {
  EXPECT_NE(error_of({"probes.1.from=[0.05]"}).find("'probes.1.from'"), std::string::npos);
  EXPECT_NE(error_of({"probes.0.type=\"speed\""}).find("'probes.0.type'"), std::string::npos);
  EXPECT_NE(error_of({"probes.3.body=0"}).find("'probes.3.body'"), std::string::npos) << "fluid body";
  EXPECT_NE(error_of({"probes.3.body=7"}).find("'probes.3.body'"), std::string::npos);
  EXPECT_NE(error_of({"probes.0.name=\"a b\""}).find("'probes.0.name'"), std::string::npos);
  EXPECT_NE(error_of({"probes.0.colour=1"}).find("probes.0.colour"), std::string::npos);
  EXPECT_NE(error_of({"probes=[{\"type\":\"pressure\",\"name\":\"x\"}]"}).find("'probes.0.point'"), std::string::npos);
  EXPECT_EQ(error_of({}), "");
  EXPECT_EQ(Probes<2>(tiny()).columns(),
            (std::vector<std::string>{"p_g1", "h_H1", "front_x", "Fx_obstacle", "Fy_obstacle", "Mz_obstacle"}));
}

TEST(Probes, HydrostaticColumnPressureHeightAndFront) {
  // the initial state is hydrostatic: p = rho0 g (H - y), H = 0.2 m, front at the column's edge
  auto s = tiny({"probes=[{\"type\":\"pressure\",\"name\":\"mid\",\"point\":[0.05,0.1]},"
                 "{\"type\":\"pressure\",\"name\":\"wall\",\"point\":[0.0,0.05]},"
                 "{\"type\":\"pressure\",\"name\":\"dry\",\"point\":[0.25,0.25]},"
                 "{\"type\":\"water_height\",\"name\":\"c\",\"from\":[0.05,0.0]},"
                 "{\"type\":\"water_height\",\"name\":\"dry\",\"from\":[0.25,0.0]},"
                 "{\"type\":\"front\"}]"});
  Simulation<2> sim(s);
  Probes<2> probes(s);
  const auto v = probes.sample(sim);
  ASSERT_EQ(v.size(), 6u);
  const double rho_g = 1000 * 9.81;
  EXPECT_NEAR(v[0], rho_g * (0.2 - 0.1), 0.05 * rho_g * 0.1);
  EXPECT_NEAR(v[1], rho_g * (0.2 - 0.05), 0.08 * rho_g * 0.15) << "on the wall: fluid neighbours only";
  EXPECT_EQ(v[2], 0.0) << "dry gauge";
  EXPECT_NEAR(v[3], 0.2, 0.5 * 0.02) << "within half a particle spacing";
  EXPECT_EQ(v[4], 0.0);
  EXPECT_NEAR(v[5], 0.09 + 0.01 * 0, 0.011);  // cell-centred lattice: largest x = 0.1 - dx/2
}

TEST(Probes, ForceOnBoundaryBodiesBalancesThePairForcesOnTheFluid) {
  // Newton's third law on the same pair terms: sum over fluid of m (a - g) = - sum over all boundary
  // particles of the reaction force (fluid-fluid pair terms cancel in the sum)
  auto s = tiny({"probes=[{\"type\":\"force\",\"name\":\"tank\",\"body\":1},{\"type\":\"force\",\"name\":\"obst\",\"body\":2}]"});
  Simulation<2> sim(s);
  for (int k = 0; k < 150; ++k) sim.advance();  // the column has collapsed onto the floor and obstacle
  Probes<2> probes(s);
  const auto v = probes.sample(sim);
  ASSERT_EQ(v.size(), 6u);
  const auto& f = sim.fields();
  std::vector<Vec<2>> a(sim.size(), Vec<2>::Zero());
  sim.rates().acceleration(sim.grid(), sim.current_view(), a.data());
  double sx = 0, sy = 0, weight = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.kind[i] != 0) continue;
    sx += f.mass[i] * a[i][0];
    sy += f.mass[i] * (a[i][1] + 9.81);
    weight += f.mass[i] * 9.81;
  }
  // float: the pair forces are accumulated in float (a few epsilon of the weight)
  EXPECT_NEAR(v[0] + v[3], -sx, test::real_tol(1e-9, 8) * weight);
  EXPECT_NEAR(v[1] + v[4], -sy, test::real_tol(1e-9, 8) * weight);
  // the fluid pushes the tank down with roughly its weight (it is mostly resting on the floor)
  EXPECT_LT(v[1], -0.3 * weight);
  EXPECT_GT(v[1], -2.0 * weight);
}

TEST(Probes, ProbesCsvFromTheBinary) {
  const auto dir = test::scratch_dir("probes_csv");
  const auto scene = test::write_scene(dir, test::tiny_dam_break());
  const auto r = test::run_command(test::varsph_exe().string() + " run '" + scene.string() + "' -o '" +
                                   (dir / "run").string() + "' --quiet --set output.probes_every=0.001");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(dir / "run" / "probes.csv");
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "time,p_g1,h_H1,front_x,Fx_obstacle,Fy_obstacle,Mz_obstacle");
  int rows = 0;
  double last_front = 0;
  for (std::string l; std::getline(in, l);) {
    ++rows;
    std::stringstream ss(l);
    std::string c;
    for (int k = 0; k < 4; ++k) std::getline(ss, c, ',');
    last_front = std::stod(c);
  }
  EXPECT_EQ(rows, 41);  // t = 0, 0.001, ..., 0.04
  EXPECT_GT(last_front, 0.095) << "the front advances";
}
