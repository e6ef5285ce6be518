#pragma once
// Small scenes for the variational integrator tests, built in code.
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "integrators/variational.hpp"
#include "scene/scene.hpp"
#include "sim/simulation.hpp"

namespace varsph::test {

// n x n lattice (spacing dx) with random velocities of scale u, in a periodic box of side n dx (periodic)
// or a free cluster in a large open domain; no gravity, no walls.
inline nlohmann::json lattice_scene(int n, double u, bool periodic, double alpha, const std::string& type,
                                    const std::string& density, double dt, double visc = 0, unsigned seed = 7,
                                    double spin = 0) {
  const double dx = 0.01, L = n * dx;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N(0.0, 1.0);
  nlohmann::json pts = nlohmann::json::array(), vel = nlohmann::json::array();
  const double off = periodic ? 0.5 * dx : 0.0;
  const double c = periodic ? 0.5 * L : 0.5 * (n - 1) * dx;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = off + i * dx, y = off + j * dx;
      pts.push_back({x, y});
      vel.push_back({u * N(rng) - spin * (y - c), u * N(rng) + spin * (x - c)});
    }
  nlohmann::json s = {
      {"name", "lattice"},
      {"setup", "paper"}, {"dimension", 2},
      {"domain", periodic ? nlohmann::json{{"min", {0.0, 0.0}}, {"max", {L, L}}, {"periodic", {true, true}}}
                          : nlohmann::json{{"min", {-1.0, -1.0}}, {"max", {1.0, 1.0}}}},
      {"particles", {{"spacing", dx}}},
      {"fluid", {{"c0", 10.0}}},
      {"gravity", {0.0, 0.0}},
      {"bodies", {{{"kind", "fluid"}, {"shape", "points"}, {"points", pts}, {"velocities", vel}}}},
      {"physics", {{"density", density}}},
      {"integrator", {{"type", type}, {"dt", dt}, {"alpha", alpha}}},
      {"time", {{"end", 1.0}}}};
  if (visc > 0) s["physics"]["artificial_viscosity"] = {{"alpha", visc}, {"beta", 0.0}};
  return s;
}

inline scene::Scene make_scene(const nlohmann::json& j, const std::vector<std::string>& overrides = {}) {
  return scene::parse_scene_json(j, "test_scene.json", overrides);
}

template <int D>
VariationalIntegrator<D>* variational_of(Simulation<D>& sim) {
  return dynamic_cast<VariationalIntegrator<D>*>(&sim.integrator());
}

// positions by id
template <int D>
std::map<std::int64_t, Vec<D>> positions_by_id(const Simulation<D>& sim) {
  std::map<std::int64_t, Vec<D>> m;
  for (std::size_t i = 0; i < sim.size(); ++i) m[sim.fields().id[i]] = sim.fields().x[i];
  return m;
}

}  // namespace varsph::test
