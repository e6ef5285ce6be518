#include "sim/scene_summary.hpp"
#include "integrators/variational.hpp"

#include <cmath>
#include <sstream>

#include "physics/pair_loop.hpp"
#include "sim/simulation.hpp"

namespace varsph {
namespace {

template <int D>
double mean_fluid_neighbours(const Simulation<D>& sim) {
  const auto& grid = sim.grid();
  const auto& x = sim.fields().x.data;
  const Real rc2 = sim.rates().support() * sim.rates().support();
  double total = 0;
  std::size_t n = 0;
  for (const auto& blk : grid.blocks())
    for (std::uint32_t i = blk.begin; i < blk.end; ++i) {
      if (sim.fields().kind[i] != 0) continue;
      ++n;
      for (std::uint32_t r = blk.nbr_begin; r < blk.nbr_end; ++r) {
        const auto nr = grid.ranges()[r];
        for (std::uint32_t j = nr.begin; j < nr.end; ++j)
          if (j != i && (x[i] - grid.shift(nr.shift) - x[j]).squaredNorm() < rc2) total += 1;
      }
    }
  return n ? total / double(n) : 0.0;
}

template <int D>
std::string describe(const scene::Scene& s) {
  Simulation<D> sim(s);
  std::ostringstream o;
  o.precision(6);
  const double support = double(sim.rates().support());
  o << "scene              " << s.name << " (" << s.file.string() << ")\n"
    << "dimension          " << D << "\n"
    << "setup              " << setup_line(s) << "\n"
    << "particles          " << sim.count(0) << " fluid, " << sim.count(1) << " boundary\n"
    << "dx                 " << s.spacing << " m\n"
    << "kernel             " << kernels::to_string(s.kernel) << ", h = " << s.h << " m (h/dx = " << s.h / s.spacing
    << "), support radius " << support << " m\n"
    << "mean neighbours    " << mean_fluid_neighbours(sim) << " (fluid particles, within the support)\n"
    << "rho0               " << s.rho0 << " kg/m^3\n"
    << "c0                 " << s.c0 << " m/s (" << s.c0_rule << ")\n"
    << "B                  " << double(sim.eos().B) << " Pa (eq. 11: c0^2 rho0 / 7)\n"
    << "density            " << s.density << "\n"
    << "viscosity          "
    << (s.artificial_viscosity ? "artificial (alpha " + std::to_string(s.av_alpha) + ", beta " +
                                     std::to_string(s.av_beta) + ") "
                               : std::string(""))
    << (s.riemann ? "Riemann-solver dissipation (Zhang 2017, eta " + std::to_string(s.riemann_eta) + ") "
                  : std::string(""))
    << (s.laminar_viscosity ? "laminar (nu " + std::to_string(s.nu) + " m^2/s)" : std::string(""))
    << (!s.artificial_viscosity && !s.laminar_viscosity && !s.riemann ? "none" : "") << "\n"
    << "density diffusion  " << (s.riemann ? std::string("riemann (pressure jump / rho0 c0)") : s.density_diffusion)
    << "\n"
    << "shifting           "
    << (s.shifting ? "A " + std::to_string(s.shift_A) + ", velocity " + s.shift_velocity + ", R " +
                         std::to_string(s.shift_R) + ", n " + std::to_string(s.shift_n) + ", free surface " +
                         s.shift_free_surface + " (div r < " + std::to_string(s.shift_fs_threshold) +
                         "), max " + std::to_string(s.shift_max) + " dx per step"
                   : std::string("none"))
    << "\n"
    << "boundary           " << s.boundary_model << " (D " << s.wall_D << " m^2/s^2, r0 " << s.wall_r0 << " m)\n"
    << "integrator         " << s.integrator << " (alpha " << s.alpha << ")\n";
  const double acoustic = s.h / s.c0;
  o << "dt                 " << (s.dt ? std::to_string(*s.dt) + " s (fixed)" : "CFL " + std::to_string(*s.cfl))
    << "\n"
    << "CFL limits         acoustic h/c0 = " << acoustic << " s; with C = 0.2: " << 0.2 * acoustic << " s";
  const double g = std::sqrt(s.gravity[0] * s.gravity[0] + s.gravity[1] * s.gravity[1] +
                             (D == 3 ? s.gravity[2] * s.gravity[2] : 0.0));
  if (g > 0) o << "; force sqrt(h/g) = " << std::sqrt(s.h / g) << " s";
  o << "\n";
  // Rough eq. (54) estimate: dt < 1 / sqrt((1 - alpha) M2) with M2 ~ c0^2 / h^2 (the stiffness of the
  // pressure term, |dH/dq| ~ B gamma / rho0 * |grad^2 W| ~ c0^2 / h^2)
  if (auto* vi = dynamic_cast<VariationalIntegrator<D>*>(&sim.integrator()); vi && !vi->explicit_scheme()) {
    // observed contraction c of the fixed-point map on the initial state (power iteration), M1 = c
    const double c = vi->estimate_contraction(sim);
    o << "variational bound  dt < " << (c > 0 ? sim.dt() / std::sqrt(c) : 0.0) << " s (eq. 54; contraction "
      << c << " at dt = " << sim.dt() << " s, M2 ~ " << c / ((1 - s.alpha) * sim.dt() * sim.dt()) << " 1/s^2)\n";
  } else if (s.integrator == "variational") {
    o << "variational bound  none (alpha = " << s.alpha << " is explicit in this setting)\n";
  } else if (s.alpha < 1) {
    const double M2 = s.c0 * s.c0 / (s.h * s.h);
    o << "variational bound  dt < " << 1.0 / std::sqrt((1 - s.alpha) * M2)
      << " s (eq. 54 with M2 ~ c0^2/h^2 = " << M2 << " 1/s^2)\n";
  } else {
    o << "variational bound  none (alpha = 1 is explicit)\n";
  }
  const auto& hs = s.health;
  o << "health             " << (hs.on_violation == "stop" ? "stop (exit 3)" : "remove") << " fluid particles outside "
    << "the domain, with |rho/rho0 - 1| > " << hs.max_density_error << " or |v| > " << hs.max_mach * s.c0
    << " m/s; exit 3 on NaN, > " << 100 * hs.max_removed_fraction << " % removed in " << hs.removal_window
    << " steps or > " << 100 * hs.max_removed_total << " % in all, energy growth > " << hs.max_energy_growth
    << " x scale (docs/scene.md \"Health\")\n";
  o << "time.end           " << s.t_end << " s, frames every " << s.output_every << " s\n";
  return o.str();
}

}  // namespace

std::string describe_scene(const scene::Scene& s) { return s.dimension == 2 ? describe<2>(s) : describe<3>(s); }

std::string setup_line(const scene::Scene& s) {
  std::string keys;
  for (const auto& k : s.setup_supplied) keys += (keys.empty() ? "" : ", ") + k;
  if (s.setup == "paper") return "paper (the paper's defaults for the method keys the scene leaves out; docs/scene.md \"Set-up\")";
  return s.setup + (keys.empty() ? " (the scene names every method key)"
                                 : " (filled in: " + keys + "; docs/scene.md \"Set-up\")");
}

}  // namespace varsph
