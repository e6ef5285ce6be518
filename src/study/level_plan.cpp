#include "study/level_plan.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/errors.hpp"
#include "scene/scene.hpp"
#include "sim/build_particles.hpp"
#include "sim/probes.hpp"
#include "sim/simulation.hpp"

namespace varsph::study {
namespace {

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

template <int D>
void count_particles(const scene::Scene& s, LevelSpec& l) {
  const auto init = build_particles<D>(s, s.c0 * s.c0 * s.rho0 / 7.0);
  l.fluid = init.count(0);
  l.boundary = init.count(1);
  l.fluid_mass = 0;
  for (std::size_t i = 0; i < init.kind.size(); ++i)
    if (init.kind[i] == 0) l.fluid_mass += double(init.mass[i]);
}

// The study's extra probes (when the scene lacks them): the surge front and the force on every boundary
// body, so front and forces are quantities of every study. Returns "probes=[...]" or "" when none is added.
std::string extra_probe_set(const scene::Scene& s) {
  nlohmann::json probes = s.probes.is_array() ? s.probes : nlohmann::json::array();
  bool front = false;
  std::vector<bool> force(s.bodies.size(), false);
  for (const auto& p : probes) {
    const std::string type = p.value("type", "");
    if (type == "front") front = true;
    if (type == "force" && p.contains("body") && p["body"].is_number_integer()) {
      const long b = p["body"].get<long>();
      if (b >= 0 && std::size_t(b) < force.size()) force[std::size_t(b)] = true;
    }
  }
  const std::size_t n0 = probes.size();
  if (!front) probes.push_back({{"type", "front"}});
  for (std::size_t b = 0; b < s.bodies.size(); ++b)
    if (s.bodies[b].kind == "boundary" && !force[b])
      probes.push_back({{"type", "force"}, {"name", "body" + std::to_string(b)}, {"body", long(b)}});
  return probes.size() == n0 ? std::string() : "probes=" + probes.dump();
}

// Parses the level's scene with its --set and fills what the plan needs from it: counts sampled, or, with
// `scaled_from`, scaled from that level's counts (fluid by volume, boundary by surface; budget candidates).
void resolve(LevelSpec& l, bool extra_probes, const LevelSpec* scaled_from = nullptr) {
  if (extra_probes) {
    const std::string extra = extra_probe_set(scene::parse_scene(l.scene, l.overrides));
    if (!extra.empty()) {
      l.overrides.push_back(extra);
      l.probe_set = extra;
    }
  }
  const scene::Scene s = scene::parse_scene(l.scene, l.overrides);
  l.name = s.name;
  l.dimension = s.dimension;
  l.dx = s.spacing;
  l.h = s.h;
  l.c0 = s.c0;
  l.t_end = s.t_end;
  l.dt = s.dt;
  l.cfl = s.cfl;
  l.dt_estimate = s.dt ? *s.dt : *s.cfl * s.h / s.c0;
  l.integrator = s.integrator;
  l.alpha = s.alpha;
  if (scaled_from) {
    const double f = scaled_from->dx / l.dx, d = double(s.dimension);
    l.fluid = std::size_t(std::llround(double(scaled_from->fluid) * std::pow(f, d)));
    l.boundary = std::size_t(std::llround(double(scaled_from->boundary) * std::pow(f, d - 1)));
    l.fluid_mass = scaled_from->fluid_mass;
  } else if (s.dimension == 2) {
    count_particles<2>(s, l);
  } else {
    count_particles<3>(s, l);
  }
}

double formal_of(Refine r, const std::string& integrator, double alpha, std::string& why) {
  const double it = integrator_order(integrator, alpha);
  const std::string it_why = integrator + (integrator == "variational" ? " (alpha " + num(alpha) + ")" : "") +
                             " is order " + num(it) + " in time";
  // the kernel approximation is second order in h (seed 004, SPH notes: f(x) = int f W dx' + O(h^2))
  if (r == Refine::Dt) {
    why = it_why;
    return it;
  }
  if (r == Refine::Dx) {
    why = "kernel approximation O(h^2) with h/dx fixed (seed 004 notes)";
    return 2.0;
  }
  why = "min of the kernel approximation's O(h^2) and " + it_why;
  return std::min(2.0, it);
}

}  // namespace

std::string LevelSpec::label() const {
  char buf[160];
  if (dt) std::snprintf(buf, sizeof buf, "dx %.4g m, dt %.3g s", dx, *dt);
  else std::snprintf(buf, sizeof buf, "dx %.4g m, CFL %.3g", dx, cfl ? *cfl : 0.0);
  return buf;
}

double integrator_order(const std::string& type, double alpha) {
  if (type == "symplectic_euler") return 1;
  if (type == "rk4") return 4;
  if (type == "variational") return std::abs(alpha - 0.5) < 1e-12 ? 2 : 1;  // generalized midpoint (eq. 63-65)
  return 2;  // verlet (eq. 60-62), verlet_dsph, predictor_corrector
}

Plan plan_levels(const StudyOptions& o, int levels, double ratio, const LevelSpec* scaled_from) {
  Plan p;
  p.refine = o.refine;
  p.ratio = ratio;
  if (o.scenes.size() > 1) {
    p.from_scenes = true;
    for (std::size_t k = 0; k < o.scenes.size(); ++k) {
      LevelSpec l;
      l.index = int(k);
      l.scene = o.scenes[k];
      l.overrides = o.overrides;
      resolve(l, o.extra_probes);
      p.levels.push_back(l);
    }
    bool same_dx = true;
    for (const auto& l : p.levels) same_dx = same_dx && std::abs(l.dx - p.levels[0].dx) <= 1e-12 * l.dx;
    p.refine = same_dx ? Refine::Dt : (o.refine == Refine::Dt ? Refine::Both : o.refine);
    for (std::size_t k = 0; k < p.levels.size(); ++k) {
      auto& l = p.levels[k];
      l.refined = p.refine == Refine::Dt ? l.dt_estimate : l.dx;
      if (k > 0 && !(l.refined < p.levels[k - 1].refined))
        throw InputError(l.scene.string() + ": the level scenes must be given coarsest first, each finer than the "
                         "one before (" + std::string(p.refine == Refine::Dt ? "integrator.dt" : "particles.spacing") +
                         " " + num(l.refined) + " after " + num(p.levels[k - 1].refined) + ")");
    }
    p.ratio = p.levels.size() > 1 ? p.levels[0].refined / p.levels[1].refined : 1.0;
    p.formal_order = formal_of(p.refine, p.levels.back().integrator, p.levels.back().alpha, p.formal_order_why);
    return p;
  }

  const auto& file = o.scenes.at(0);
  const scene::Scene s = scene::parse_scene(file, o.overrides);
  if (o.refine != Refine::Dt)
    for (std::size_t b = 0; b < s.bodies.size(); ++b)
      if (s.bodies[b].shape == "points")
        throw InputError(file.string() + ": key 'bodies." + std::to_string(b) +
                         ".shape': a \"points\" body has explicit positions and cannot be refined in dx; give one "
                         "scene per level (varsph study L0.json L1.json L2.json, coarsest first) or --refine dt");
  const bool h_given = s.resolved.contains("kernel") && s.resolved["kernel"].contains("h");
  const double dx0 = o.coarsest_dx > 0 ? o.coarsest_dx : s.spacing;
  const double scale0 = dx0 / s.spacing;  // --dx keeps the scene's h/dx and CFL number
  for (int k = 0; k < levels; ++k) {
    LevelSpec l;
    l.index = k;
    l.scene = file;
    const double rk = std::pow(ratio, k);
    const double rdt = o.refine == Refine::Dx ? std::pow(ratio, levels - 1) : rk;
    const double dxk = o.refine == Refine::Dt ? dx0 : dx0 / rk;
    if (o.refine != Refine::Dt || o.coarsest_dx > 0) {
      l.level_sets.push_back("particles.spacing=" + num(dxk));
      if (h_given) l.level_sets.push_back("kernel.h=" + num(s.h * dxk / s.spacing));
    }
    if (s.dt) {
      l.level_sets.push_back("integrator.dt=" + num(*s.dt * scale0 / rdt));
    } else {
      // CFL number: unchanged when dx and dt are refined together; smaller to refine dt (dt) or to hold every
      // level at the finest level's step (dx)
      const double c = o.refine == Refine::Both ? *s.cfl : o.refine == Refine::Dt ? *s.cfl / rk
                                                                                   : *s.cfl * rk / rdt;
      if (o.refine != Refine::Both) l.level_sets.push_back("integrator.cfl=" + num(c));
    }
    l.overrides = o.overrides;
    l.overrides.insert(l.overrides.end(), l.level_sets.begin(), l.level_sets.end());
    resolve(l, o.extra_probes, scaled_from);
    l.refined = o.refine == Refine::Dt ? l.dt_estimate : l.dx;
    p.levels.push_back(l);
  }
  p.formal_order = formal_of(p.refine, s.integrator, s.alpha, p.formal_order_why);
  return p;
}

LevelSpec variant_level(const LevelSpec& base, const std::vector<std::string>& extra_sets) {
  LevelSpec l = base;
  l.overrides.insert(l.overrides.end(), extra_sets.begin(), extra_sets.end());
  resolve(l, false);
  return l;
}

void validate_level(const LevelSpec& level) {
  const scene::Scene s = scene::parse_scene(level.scene, level.overrides);
  if (s.dimension == 2) {
    Simulation<2> sim(s);
    Probes<2> probes(s);
  } else {
    Simulation<3> sim(s);
    Probes<3> probes(s);
  }
}

std::string resolved_scene_json(const LevelSpec& level) {
  return scene::parse_scene(level.scene, level.overrides).resolved.dump();
}

Prediction predict_cost(const Measured& m, const LevelSpec& l) {
  Prediction p;
  if (l.dt) p.steps = std::round(l.t_end / *l.dt);
  else p.steps = double(m.steps) * (m.dt_estimate / l.dt_estimate) * (l.t_end / m.t_end);
  p.particle_steps = p.steps * double(l.fluid);
  const double mps = double(m.steps) * double(std::max<std::size_t>(m.fluid, 1));
  p.wall = m.wall / mps * p.particle_steps;
  p.cpu = m.cpu / mps * p.particle_steps;
  const double per_particle =
      std::max(m.rss_mb - m.baseline_rss_mb, 0.0) / double(std::max<std::size_t>(m.fluid + m.boundary, 1));
  p.rss_mb = m.baseline_rss_mb + per_particle * double(l.fluid + l.boundary);
  return p;
}

double current_rss_mb() {
  std::ifstream in("/proc/self/statm");
  long pages_total = 0, pages_resident = 0;
  if (!(in >> pages_total >> pages_resident)) return 0;
  return double(pages_resident) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

double available_memory_mb() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kb = 0;
  std::string unit;
  while (in >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb / 1024.0;
  return 0;
}

}  // namespace varsph::study
