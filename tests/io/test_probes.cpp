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

TEST(Probes, WallSensorIsExactOnTheHydrostaticColumnWithAndWithoutAFace) {
  // first-order fluid-side value: the linear hydrostatic field is read exactly on the wall (x = 0) and on
  // the floor (y = 0), with a point sensor and with a 15 mm face (a linear field's face mean is its centre
  // value); the wall normal is found from the nearest wall particle; a sensor far from any fluid reads 0
  auto s = tiny({"probes=[{\"type\":\"pressure\",\"name\":\"w\",\"point\":[0.0,0.08]},"
                 "{\"type\":\"pressure\",\"name\":\"wr\",\"point\":[0.0,0.08],\"radius\":0.015},"
                 "{\"type\":\"pressure\",\"name\":\"f\",\"point\":[0.05,0.0],\"radius\":0.015},"
                 "{\"type\":\"pressure\",\"name\":\"fn\",\"point\":[0.05,0.0],\"normal\":[0,2]},"
                 "{\"type\":\"pressure\",\"name\":\"dry\",\"point\":[0.4,0.2],\"radius\":0.01}]"});
  Simulation<2> sim(s);
  Probes<2> probes(s);
  const auto v = probes.sample(sim);
  ASSERT_EQ(v.size(), 5u);
  const double rho_g = 1000 * 9.81, tol = test::real_tol(1e-6, 1e3) * rho_g * 0.2;
  EXPECT_NEAR(v[0], rho_g * (0.2 - 0.08), tol);
  EXPECT_NEAR(v[1], rho_g * (0.2 - 0.08), tol);
  EXPECT_NEAR(v[2], rho_g * 0.2, tol) << "floor";
  EXPECT_NEAR(v[3], rho_g * 0.2, tol) << "given normal (normalised)";
  EXPECT_EQ(v[4], 0.0) << "dry sensor";
  // a face radius without a normal and no wall nearby is refused, naming the probe
  auto bad = tiny({"probes=[{\"type\":\"pressure\",\"name\":\"lost\",\"point\":[0.2,0.2],\"radius\":0.01}]"});
  Simulation<2> sim2(bad);
  Probes<2> p2(bad);
  try {
    p2.sample(sim2);
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'lost'"), std::string::npos) << e.what();
  }
}

TEST(Probes, LoadProbesReportTheMeanOverTheSamplingInterval) {
  // a row is the dt-weighted mean of the per-step values since the previous row (a transducer integrates
  // over its sampling interval); geometric probes are instantaneous
  auto s = tiny({"probes=[{\"type\":\"pressure\",\"name\":\"w\",\"point\":[0.0,0.02]},{\"type\":\"front\"}]"});
  Simulation<2> sim(s);
  Probes<2> averaged(s), instant(s);
  double sum = 0, T = 0;
  for (int k = 0; k < 40; ++k) {
    sim.advance();
    averaged.accumulate(sim);
    const auto now = instant.sample(sim);  // nothing accumulated: the current value
    sum += now[0] * sim.dt();
    T += sim.dt();
  }
  const auto row = averaged.sample(sim);
  const auto now = instant.sample(sim);
  EXPECT_NEAR(row[0], sum / T, 1e-9 * std::abs(sum / T));
  EXPECT_NE(row[0], now[0]) << "the column is collapsing: the mean differs from the last value";
  EXPECT_EQ(row[1], now[1]) << "the front is instantaneous";
  // the accumulation round-trips through the checkpoint state
  Probes<2> a(s), b(s);
  a.accumulate(sim);
  a.accumulate(sim);
  b.restore_state(a.save_state());
  EXPECT_EQ(a.sample(sim), b.sample(sim));
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
