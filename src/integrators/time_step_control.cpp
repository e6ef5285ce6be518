#include "integrators/time_step_control.hpp"

#include <algorithm>
#include <cmath>

#include "core/team.hpp"
#include "sim/simulation.hpp"

namespace varsph {

double CflLimits::dt() const { return std::min({acoustic, force, viscous}); }

const char* CflLimits::binding() const {
  const double d = dt();
  if (d == acoustic) return "acoustic";
  if (d == force) return "force";
  return "viscous";
}

template <int D>
double effective_viscosity(const Simulation<D>& sim) {
  const auto& s = sim.scene();
  double nu = 0;
  // Monaghan 2005 (Rep. Prog. Phys. 68), eq. (4.14): nu = alpha c h / (2 (d + 2)) for Monaghan's Pi_ij
  if (s.artificial_viscosity) nu += s.av_alpha * s.c0 * s.h / (2.0 * (D + 2));
  // physical viscosity (Morris et al. 1997: dt <= 0.125 h^2 / nu with the default coefficient)
  if (sim.params().laminar_viscosity) nu += double(sim.params().nu);
  return nu;
}

template <int D>
CflLimits cfl_limits(const Simulation<D>& sim) {
  const auto& f = sim.fields();
  // maxima are exact in any order: the same dt for any thread count, in or out of a step region
  const auto [vmax, amax] = team_max2(long(sim.size()), [&](long i, double& vm, double& am) {
    if (f.kind[i] != 0) return;
    vm = std::max(vm, double(f.v[i].norm()));
    am = std::max(am, double(f.a[i].norm()));
  });
  return cfl_limits(sim, sim.global_max(vmax), sim.global_max(amax));  // over every rank: the same dt
}

template <int D>
CflLimits cfl_limits(const Simulation<D>& sim, double vmax, double amax) {
  const auto& s = sim.scene();
  CflLimits L;
  L.v_max = vmax;
  L.a_max = amax;
  const double h = s.h;
  L.acoustic = s.cfl_acoustic * h / (s.c0 + L.v_max);                // Monaghan 1992
  if (L.a_max > 0) L.force = s.cfl_force * std::sqrt(h / L.a_max);   // Monaghan 1992
  L.nu = effective_viscosity(sim);
  if (L.nu > 0) L.viscous = s.cfl_viscous * h * h / L.nu;            // Morris et al. 1997
  return L;
}

template double effective_viscosity<2>(const Simulation<2>&);
template double effective_viscosity<3>(const Simulation<3>&);
template CflLimits cfl_limits<2>(const Simulation<2>&);
template CflLimits cfl_limits<3>(const Simulation<3>&);
template CflLimits cfl_limits<2>(const Simulation<2>&, double, double);
template CflLimits cfl_limits<3>(const Simulation<3>&, double, double);

}  // namespace varsph
