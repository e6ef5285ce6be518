// Validation (issue 32): a laminar free-surface film down a slope with a free-surface inlet (water level
// imposed) and an outlet (pipelines/open/film_slope.json, docs/validation.md section 19). Steady uniform film
// of depth H on a bed inclined at alpha (the Nusselt film; e.g. Bird, Stewart & Lightfoot, Transport
// Phenomena, sec. 2.2): u(y) = g sin(alpha) / nu (H y - y^2 / 2), surface speed u_s = g sin(alpha) H^2 / (2 nu),
// flow rate q = g sin(alpha) H^3 / (3 nu); y is the distance from the bed, the gravity vector is tilted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "sim/open_boundaries.hpp"
#include "sim/simulation.hpp"
#include "test_support.hpp"

using namespace varsph;

namespace {

struct Film {
  double profile_error = 0;  // max over rows of |mean (u_i - u(y_i))| / u_s, fluid in the middle third
  double depth = 0;          // film depth: mean over columns of the top particle's y + dx / 2 [m]
  double flux = 0;           // sum of V_i u_i over the middle third / its length [m^2/s]
  double balance = 0;        // |mass_in - mass_out - (M - M0)| / M0
  double mass_ratio = 0;     // M / M0
  long created = 0, removed = 0;
};

Film measure(Simulation<2>& sim, double G, double nu, double H, double x_lo, double x_hi) {
  const auto& f = sim.fields();
  const auto& zone = sim.store().get<std::int32_t>("open_zone");
  const double dx = sim.scene().spacing;
  const double us = G * H * H / (2 * nu);
  std::map<long, std::pair<double, double>> rows;  // row -> (sum of u - u_exact, count)
  std::map<long, double> top;                      // column -> highest y
  double flux = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.kind[i] != 0 || zone[i] >= 0) continue;
    const double x = f.x[i][0], y = f.x[i][1];
    if (x < x_lo || x > x_hi) continue;
    const double yc = std::clamp(y, 0.0, H);
    const double exact = G / nu * (H * yc - yc * yc / 2);
    auto& r = rows[long(std::floor(y / dx))];
    r.first += f.v[i][0] - exact;
    r.second += 1;
    auto& t = top[long(std::floor(x / dx))];
    t = std::max(t, y);
    flux += double(f.mass[i]) / double(f.rho[i]) * f.v[i][0];
  }
  Film m;
  for (const auto& [row, r] : rows) m.profile_error = std::max(m.profile_error, std::abs(r.first / r.second) / us);
  for (const auto& [col, y] : top) m.depth += (y + dx / 2) / double(top.size());
  m.flux = flux / (x_hi - x_lo);
  const auto& fl = sim.flow();
  m.balance = std::abs(fl.mass_in - fl.mass_out() - (sim.fluid_mass() - fl.mass0)) / fl.mass0;
  m.mass_ratio = sim.fluid_mass() / fl.mass0;
  m.created = fl.created;
  m.removed = fl.removed_outlet;
  return m;
}

// VARSPH_OPEN_FILM_SET="key=value;key=value": --set overrides (the resolution and duration studies of
// docs/validation.md section 19); without it the scene as committed
std::vector<std::string> overrides_from_environment() {
  std::vector<std::string> out;
  const char* env = std::getenv("VARSPH_OPEN_FILM_SET");
  std::string rest = env ? env : "";
  for (std::size_t at; !rest.empty(); rest = at == std::string::npos ? "" : rest.substr(at + 1)) {
    at = rest.find(';');
    if (const std::string one = rest.substr(0, at); !one.empty()) out.push_back(one);
  }
  return out;
}

}  // namespace

TEST(OpenFilmValidation, NusseltProfileFluxDepthAndMassBalance) {
  const scene::Scene s = scene::parse_scene(test::source_dir() / "pipelines/open/film_slope.json", overrides_from_environment());
  Simulation<2> sim(s);
  const double G = s.gravity[0];  // g sin(alpha): the tilted gravity's component along the bed
  const double nu = s.nu, H = s.open_boundaries[0].level, L = s.bodies[0].max[0];
  const double us = G * H * H / (2 * nu), q_exact = G * H * H * H / (3 * nu);
  std::vector<double> marks = {0.6 * s.t_end, 0.8 * s.t_end};
  while (sim.time() < s.t_end - 0.5 * sim.dt()) {
    sim.advance();
    if (!marks.empty() && sim.time() >= marks.front()) {
      const Film m = measure(sim, G, nu, H, L / 3, 2 * L / 3);
      std::printf("  t = %.3f s: profile %.2f %% of u_s, depth %.3f H, flux %.4f q, mass %.4f M0\n", sim.time(),
                  100 * m.profile_error, m.depth / H, m.flux / q_exact, m.mass_ratio);
      marks.erase(marks.begin());
    }
  }
  const Film m = measure(sim, G, nu, H, L / 3, 2 * L / 3);
  std::printf("open film dx %.3g (H/dx %.0f) at t = %.3g s (%ld steps): profile error %.2f %% of u_s = %.4f m/s, "
              "depth %.4f H, flux %.4f q_exact, mass %.4f M0, mass balance %.3g of M0, created %ld, removed %ld\n",
              s.spacing, H / s.spacing, sim.time(), sim.step(), 100 * m.profile_error, us, m.depth / H, m.flux / q_exact,
              m.mass_ratio, m.balance, m.created, m.removed);
  // measured at t = 1 s, H/dx = 20 (docs/validation.md section 19): profile 0.32 % of u_s, flux +0.13 %, depth
  // -0.33 % (the top particle + dx/2, a measure quantised by dx = 5 % of H, averaged over the columns); the
  // tolerances are 1 % (the goal for the Poiseuille profile), three times what is measured, and a
  // departure of the depth or the flux by 1 % would be a free-surface inlet that does not keep its level or flux
  EXPECT_LT(m.profile_error, 0.01);
  EXPECT_LT(std::abs(m.flux / q_exact - 1), 0.01);
  EXPECT_LT(std::abs(m.depth / H - 1), 0.01);
  EXPECT_LT(m.balance, 1e-12);
  EXPECT_GT(m.created, 0);
  EXPECT_GT(m.removed, 0);
}
