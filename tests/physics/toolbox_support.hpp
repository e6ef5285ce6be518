#pragma once
// Small scenes built in code for the toolbox tests (tests/physics/test_toolbox*.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "kernels/kernel_eval.hpp"
#include "scene/scene.hpp"
#include "sim/diagnostics.hpp"
#include "sim/simulation.hpp"

namespace varsph::toolbox_test {

using nlohmann::json;

// A tank [0, W] x [0, top] with `layers` wall layers, fluid [0, W] x [0, H], at rest.
inline json tank_scene(double W, double H, double dx, const std::string& model, int layers = 4) {
  const double pad = (layers + 1) * dx;
  json j = {
      {"name", "toolbox_tank"},
      {"setup", "paper"}, {"dimension", 2},
      {"domain", {{"min", {-pad, -pad}}, {"max", {W + pad, 1.6 * H + pad}}}},
      {"particles", {{"spacing", dx}}},
      {"kernel", {{"type", "gaussian"}, {"h_over_dx", 1.2}}},
      {"fluid", {{"rho0", 1000.0}, {"c0", "auto"}, {"c0_factor", 10}}},
      {"gravity", {0.0, -9.81}},
      {"bodies",
       {{{"kind", "fluid"}, {"shape", "box"}, {"min", {0.0, 0.0}}, {"max", {W, H}}, {"initial_pressure", "hydrostatic"}},
        {{"kind", "boundary"}, {"shape", "tank"}, {"min", {0.0, 0.0}}, {"max", {W, 1.5 * H}}, {"layers", layers}}}},
      {"physics", {{"density", "continuity"}, {"artificial_viscosity", {{"alpha", 0.1}, {"beta", 0.0}}}}},
      {"boundary", {{"model", model}}},
      {"integrator", {{"type", "verlet"}, {"cfl", 0.2}}},
      {"time", {{"end", 1.0}}}};
  return j;
}

inline scene::Scene parse(const json& j) { return scene::parse_scene_json(j, "toolbox_test.json"); }

template <int D>
void run_until(Simulation<D>& sim, double t) {
  while (sim.time() < t - 0.5 * sim.dt()) {
    sim.advance();
    ASSERT_EQ(check_health(sim), "") << "at step " << sim.step();
  }
}

// Shepard interpolation of the fluid pressure at a point: sum_j p_j V_j W / sum_j V_j W (fluid only).
inline double shepard_pressure(const Simulation<2>& sim, const Vec<2>& at) {
  const auto& s = sim.scene();
  kernels::AnyKernel<2> W(s.kernel, s.h, s.kernel_l);
  const auto& f = sim.fields();
  double num = 0, den = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.kind[i] != 0) continue;
    const double r = (f.x[i] - at).norm();
    if (r >= W.support()) continue;
    const double vw = f.mass[i] / f.rho[i] * W(Real(r)).w;
    num += f.p[i] * vw;
    den += vw;
  }
  return den > 0 ? num / den : 0.0;
}

inline double kinetic_energy(const Simulation<2>& sim) {
  double e = 0;
  const auto& f = sim.fields();
  for (std::size_t i = 0; i < sim.size(); ++i)
    if (f.kind[i] == 0) e += 0.5 * f.mass[i] * f.v[i].squaredNorm();
  return e;
}

}  // namespace varsph::toolbox_test
