// Density diffusion (delta-SPH): pressure noise std(p - rho0 g depth) of the fluid in a settled tank,
// without diffusion, with Molteni & Colagrossi (2009), Fourtakas et al. (2019) and Antuono et al. (2010).
#include "toolbox_support.hpp"

using namespace varsph;
using namespace varsph::toolbox_test;

namespace {

#ifndef TOOLBOX_DIFFUSION_DX
#define TOOLBOX_DIFFUSION_DX 0.02  // fast tier; the validation build uses 0.01
#endif

double pressure_noise(const std::string& type) {
  const double W = 0.3, H = 0.2, dx = TOOLBOX_DIFFUSION_DX, rho0 = 1000, g = 9.81, t_end = 1.0;
  json j = tank_scene(W, H, dx, "dynamic");
  if (type != "none") j["physics"]["density_diffusion"] = {{"type", type}, {"delta", 0.1}};
  Simulation<2> sim(parse(j));
  run_until(sim, t_end);
  const auto& f = sim.fields();
  double s = 0, s2 = 0;
  int n = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    if (f.kind[i] != 0) continue;
    const double e = f.p[i] - rho0 * g * (H - f.x[i][1]);
    s += e;
    s2 += e * e;
    ++n;
  }
  const double mean = s / n, sd = std::sqrt(std::max(0.0, s2 / n - mean * mean));
  std::printf("[%s] dx = %.3f m, t = %.1f s: pressure noise std(p - rho0 g depth) = %.1f Pa (%.2f %% of rho0 g H), mean %.1f Pa\n",
              type.c_str(), dx, t_end, sd, 100 * sd / (rho0 * g * H), mean);
  return sd;
}

}  // namespace

TEST(DensityDiffusion, ReducesPressureNoiseInASettledTank) {
  const double none = pressure_noise("none");
  const double molteni = pressure_noise("molteni");
  const double fourtakas = pressure_noise("fourtakas");
  const double antuono = pressure_noise("antuono");
  std::printf("noise ratio: molteni / none = %.3f, fourtakas / none = %.3f, antuono / none = %.3f\n", molteni / none,
              fourtakas / none, antuono / none);
  EXPECT_LT(fourtakas, 0.5 * none);
  EXPECT_LT(antuono, 0.5 * none);  // renormalised: no diffusion of the stratification, as Fourtakas
  EXPECT_LT(molteni, none);
}
