// Scene schema: every key, its default, range and unit. docs/scene.md mirrors this file.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/errors.hpp"
#include "scene/json_reader.hpp"
#include "scene/parse_health.hpp"
#include "scene/parse_open.hpp"
#include "scene/parse_rigid.hpp"
#include "scene/sanity.hpp"
#include "scene/scene.hpp"

namespace varsph::scene {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string at(const std::string& base, const std::string& key) { return base + "." + key; }

// `wall_layers`: the default of a boundary body's `layers` (1, or under the engineering set-up the kernel
// support in spacings for a pressure wall; apply_setup below)
BodySpec parse_body(JsonReader& r, const std::string& base, int dim, int wall_layers) {
  r.expect_keys(base, {"kind", "shape", "min", "max", "open", "layers", "center", "radius", "points", "velocities",
                       "velocity", "initial_pressure", "free_surface", "pressures", "mesh", "fill", "layer_side",
                       "transform", "section", "clip_min", "clip_max", "allow_self_intersections", "motion"});
  BodySpec b;
  b.kind = r.choice(at(base, "kind"), std::nullopt, {"fluid", "boundary", "rigid"});
  b.shape = r.choice(at(base, "shape"), r.has(at(base, "mesh")) ? std::optional<std::string>("mesh") : std::nullopt,
                     {"box", "tank", "sphere", "cylinder", "points", "mesh"});
  if (b.shape == "cylinder" && b.kind != "rigid") r.fail(at(base, "shape"), "\"cylinder\" only for a rigid body");
  if (b.kind == "rigid" && (b.shape == "tank" || b.shape == "points"))
    r.fail_got(at(base, "shape"), "\"box\", \"sphere\", \"cylinder\" or \"mesh\" for a rigid body", json(b.shape));
  const std::vector<double> zero(dim, 0.0);
  b.velocity = r.vector(at(base, "velocity"), dim, zero, "initial velocity [m/s]");
  if (b.shape == "box" || b.shape == "tank") {
    b.min = r.vector(at(base, "min"), dim, std::nullopt, "lower corner [m]");
    b.max = r.vector(at(base, "max"), dim, std::nullopt, "upper corner [m]");
    for (int a = 0; a < dim; ++a)
      if (!(b.max[a] > b.min[a]))
        r.fail(at(base, "max"), "max > min on every axis (axis " + std::to_string(a) + " is empty)");
  }
  if (b.shape == "tank") {
    if (b.kind != "boundary") r.fail(at(base, "kind"), "\"boundary\" for a tank");
    std::vector<bool> def(2 * dim, false);
    def[2 * (dim - 1) + 1] = true;  // open top by default
    b.open = r.bools(at(base, "open"), 2 * dim, def);
  }
  if (b.shape == "sphere" || b.shape == "cylinder") {
    b.center = r.vector(at(base, "center"), dim, std::nullopt, "centre [m]");
    b.radius = r.positive(at(base, "radius"), std::nullopt, "radius [m]");
  }
  if (b.shape == "points") {
    const json* pts = r.raw(at(base, "points"));
    if (!pts || !pts->is_array() || pts->empty()) r.fail(at(base, "points"), "a non-empty array of positions");
    const std::size_t n = pts->size();
    for (std::size_t k = 0; k < n; ++k)
      b.points.push_back(r.vector(at(base, "points." + std::to_string(k)), dim, std::nullopt, "position [m]"));
    r.subtree(at(base, "points"), *pts);
    if (const json* vel = r.raw(at(base, "velocities"))) {
      if (!vel->is_array() || vel->size() != n)
        r.fail_got(at(base, "velocities"), "an array with one velocity per point", *vel);
      for (std::size_t k = 0; k < n; ++k)
        b.velocities.push_back(
            r.vector(at(base, "velocities." + std::to_string(k)), dim, std::nullopt, "velocity [m/s]"));
      r.subtree(at(base, "velocities"), *vel);
    }
    if (const json* pr = r.raw(at(base, "pressures"))) {
      if (!pr->is_array() || pr->size() != n) r.fail_got(at(base, "pressures"), "an array with one pressure [Pa] per point", *pr);
      for (const auto& v : *pr) {
        if (!v.is_number()) r.fail_got(at(base, "pressures"), "numbers [Pa]", *pr);
        b.pressures.push_back(v.get<double>());
      }
      r.subtree(at(base, "pressures"), *pr);
    }
  }
  if (b.shape == "mesh") {
    // mesh bodies: keys validated by the geometry module (docs/geometry.md)
    b.mesh = json::object();
    for (const char* key : {"mesh", "transform", "fill", "layer_side", "section", "clip_min", "clip_max",
                            "allow_self_intersections"}) {
      if (const json* v = r.raw(at(base, key))) b.mesh[key] = *v;
      if (r.raw(at(base, key))) r.subtree(at(base, key), *r.raw(at(base, key)));
    }
    if (!b.mesh.contains("mesh")) r.fail(at(base, "mesh"), "a mesh file path (relative to the scene file)");
  }
  if (b.kind == "boundary") {
    if (wall_layers > 1 && !r.has(at(base, "layers"))) r.supply(at(base, "layers"), wall_layers, "engineering");
    b.layers = int(r.integer(at(base, "layers"), 1, 1, 16));
    // validated with its law by sim/boundary_motion.cpp (errors name bodies.N.motion.KEY)
    if (r.raw(at(base, "motion"))) b.motion = r.subtree(at(base, "motion"), json());  // null: fixed
  }
  if (b.kind == "rigid") parse_rigid_body(r, base, dim, b);  // scene/parse_rigid.cpp
  if (b.kind == "fluid") {
    b.initial_pressure = r.choice(at(base, "initial_pressure"), "zero", {"zero", "hydrostatic"});
    if (b.initial_pressure == "hydrostatic") {
      double top = 0;
      if (!b.max.empty()) top = b.max[dim - 1];
      else if (!b.center.empty()) top = b.center[dim - 1] + b.radius;
      b.free_surface = r.number(at(base, "free_surface"), top, -kInf, kInf, "free-surface level [m]");
    }
  }
  return b;
}

// The set-up (top-level `setup`, issue 35; docs/scene.md "Set-up"): the defaults of the method keys a scene
// leaves out. "engineering" (the default) is the recommended set-up of pipelines/engineering_2d.json and
// engineering_3d.json (README "The recommended engineering set-up"); "paper" is the seed paper's, the
// defaults of the tables in docs/scene.md, which is what every scene ran with before the key existed. A key
// the scene (or --set) names always wins; the set-up fills in, key by key, only what is left out, so a scene
// can change one choice and keep the rest. The pressure dissipation is one choice, not a key: the set-up's
// Riemann solver only where the scene names none of physics.riemann, artificial_viscosity and
// density_diffusion (a key set to null names "none", as `varsph study --ablate` does). Returns the set-up.
std::string apply_setup(JsonReader& r) {
  const std::string setup = r.choice("setup", "engineering", {"engineering", "paper"});
  if (setup == "paper") return setup;
  const auto block_open = [&](const std::string& block) {  // absent, null or an object (else: its own error)
    const json* b = r.raw(block);
    return !b || b->is_null() || b->is_object();
  };
  if (block_open("kernel")) {
    if (!r.has("kernel.type")) r.supply("kernel.type", "wendland_c2", setup);
    const json* t = r.raw("kernel.type");
    if (t->is_string() && t->get<std::string>() == "wendland_c2" && !r.has("kernel.h") && !r.has("kernel.h_over_dx"))
      r.supply("kernel.h_over_dx", 1.414, setup);  // DualSPHysics' 2D h (README, docs/validation.md 16)
  }
  if (block_open("physics") && !r.raw("physics.riemann") && !r.raw("physics.artificial_viscosity") &&
      !r.raw("physics.density_diffusion"))
    r.supply("physics.riemann", json::object(), setup);  // Zhang, Hu & Adams 2017, eta 3
  if (block_open("boundary") && !r.has("boundary.model")) r.supply("boundary.model", "dummy_adami", setup);
  if (block_open("integrator")) {
    if (!r.has("integrator.type")) r.supply("integrator.type", "symplectic_euler", setup);
    if (!r.has("integrator.dt") && !r.has("integrator.cfl")) r.supply("integrator.cfl", 0.2, setup);
  }
  return setup;
}

}  // namespace

Scene parse_scene_json(json root, const std::filesystem::path& file, const std::vector<std::string>& overrides) {
  const std::string fname = file.string();
  if (!root.is_object()) throw InputError(fname + ": expected a JSON object at the top level");
  for (const auto& o : overrides) apply_override(root, o, fname);
  JsonReader r(std::move(root), fname);
  r.note_overrides(overrides);
  const std::string setup = apply_setup(r);
  r.expect_keys("physics", {"density", "artificial_viscosity", "laminar_viscosity", "body_force", "xsph", "damping",
                            "damping_zone", "gravity_ramp", "density_diffusion", "riemann", "tensile_instability", "shepard_reinit",
                            "shifting"});
  Scene s;
  s.file = file;
  s.setup = setup;
  s.name = r.text("name", std::nullopt);
  if (s.name.empty() || s.name.find_first_of("/\\ ") != std::string::npos)
    r.fail_got("name", "a non-empty name without spaces or slashes", json(s.name));
  s.dimension = int(r.integer("dimension", std::nullopt, 2, 3));
  const int d = s.dimension;

  s.domain_min = r.vector("domain.min", d, std::nullopt, "lower corner of the domain [m]");
  s.domain_max = r.vector("domain.max", d, std::nullopt, "upper corner of the domain [m]");
  for (int a = 0; a < d; ++a)
    if (!(s.domain_max[a] > s.domain_min[a]))
      r.fail_got("domain.max", "domain.max > domain.min on every axis (the domain is empty on axis " +
                                   std::to_string(a) + ")", json(s.domain_max));
  s.periodic = r.bools("domain.periodic", d, std::vector<bool>(d, false));
  s.neighbor_search = r.choice("domain.neighbor_search", "cell", {"cell", "hash"});

  s.spacing = r.positive("particles.spacing", std::nullopt, "particle spacing dx [m]");
  // read by sim/particle_budget.cpp from the resolved scene
  r.number("particles.max_count", 1e7, 1, 1e12, "largest number of particles the bodies may produce (estimated before sampling)");
  s.min_boundary_distance =
      s.spacing * r.number("particles.min_boundary_distance", 0.5, 0, 10, "fluid-boundary clearance in units of dx");

  const std::string ktype =
      r.choice("kernel.type", "gaussian", {"gaussian", "cubic_spline", "wendland_c2", "paper_literal"});
  kernels::parse_kernel_type(ktype, s.kernel);
  if (r.has("kernel.h")) {
    s.h = r.positive("kernel.h", std::nullopt, "smoothing length h [m]");
  } else {
    const double ratio = r.number("kernel.h_over_dx", 1.2, 0.5, 10, "h/dx");
    s.h = ratio * s.spacing;
  }
  s.kernel_tabulated = r.boolean("kernel.tabulated", true);
  if (s.kernel == kernels::KernelType::PaperLiteral) s.kernel_l = r.positive("kernel.l", 9.47, "kernel constant l");

  s.gravity = r.vector("gravity", d, std::vector<double>(d, 0.0), "gravitational acceleration [m/s^2]");
  s.rho0 = r.positive("fluid.rho0", 1000.0, "rest density rho0 [kg/m^3]");

  // a boundary body's `layers`: 1 (the paper's repulsive walls need no more); under the engineering set-up a
  // pressure wall (every model but "repulsive") is as deep as the kernel's support, ceil(kappa h / dx) layers,
  // so that a fluid particle at the wall sees a full support of wall particles
  int wall_layers = 1;
  if (setup == "engineering") {
    const json* model = r.raw("boundary.model");
    if (model && model->is_string() && model->get<std::string>() != "repulsive")
      wall_layers = int(std::clamp(std::ceil(kernels::kappa_of(s.kernel) * s.h / s.spacing - 1e-9), 1.0, 16.0));
  }
  const std::size_t nb = r.array_size("bodies");
  if (nb == 0) r.fail("bodies", "a non-empty list of bodies (at least one with kind \"fluid\")");
  bool any_fluid = false;
  double fluid_height = 0;
  for (std::size_t k = 0; k < nb; ++k) {
    s.bodies.push_back(parse_body(r, "bodies." + std::to_string(k), d, wall_layers));
    const BodySpec& b = s.bodies.back();
    if (b.kind == "fluid") {
      any_fluid = true;
      if (!b.max.empty()) fluid_height = std::max(fluid_height, b.max[d - 1] - b.min[d - 1]);
      if (!b.center.empty()) fluid_height = std::max(fluid_height, 2 * b.radius);
    }
  }
  if (!any_fluid) r.fail("bodies", "at least one body with \"kind\": \"fluid\"");
  parse_moorings_and_contact(r, s);  // scene/parse_rigid.cpp
  parse_open_boundaries(r, s);       // scene/parse_open.cpp

  // speed of sound: a number, or "auto" = factor x max(sqrt(2 g H), reference speed)
  const double g = std::sqrt([&] { double q = 0; for (double x : s.gravity) q += x * x; return q; }());
  const json* c0 = r.raw("fluid.c0");
  if (c0 && c0->is_number()) {
    s.c0 = r.positive("fluid.c0", std::nullopt, "speed of sound c0 [m/s]");
    s.c0_rule = "given";
    // with a given c0 the scales only inform the scene check's Mach warning (scene/sanity.cpp)
    if (r.has("fluid.reference_height"))
      s.reference_height = r.number("fluid.reference_height", 0.0, 0, kInf, "height H of the fluid [m]");
    if (r.has("fluid.reference_speed"))
      s.reference_speed = r.number("fluid.reference_speed", 0.0, 0, kInf, "largest expected speed [m/s]");
  } else {
    if (c0 && !(c0->is_string() && c0->get<std::string>() == "auto"))
      r.fail_got("fluid.c0", "a positive number [m/s] or \"auto\"", *c0);
    r.text("fluid.c0", "auto");
    const double factor = r.positive("fluid.c0_factor", 10.0, "c0 factor");
    const bool named_h = r.has("fluid.reference_height"), named_u = r.has("fluid.reference_speed");
    const double H = r.number("fluid.reference_height", fluid_height, 0, kInf, "height H of the fluid [m]");
    const double u_ref = r.number("fluid.reference_speed", 0.0, 0, kInf, "largest expected speed [m/s]");
    if (named_h) s.reference_height = H;
    if (named_u) s.reference_speed = u_ref;
    const double u = std::max(std::sqrt(2 * g * H), u_ref);
    if (!(u > 0))
      r.fail("fluid.c0", "a number, or gravity and a fluid height / fluid.reference_speed for \"auto\"");
    s.c0 = factor * u;
    s.c0_rule = "auto: " + std::to_string(factor) + " x max(sqrt(2 g H), reference_speed)";
  }

  s.background_pressure = r.number("fluid.background_pressure", 0.0, 0, kInf, "background pressure p_b [Pa]");
  s.density = r.choice("physics.density", "continuity", {"continuity", "summation"});
  if (r.has("physics.artificial_viscosity")) {
    s.artificial_viscosity = true;
    const json* av = r.raw("physics.artificial_viscosity");
    if (!av->is_object()) r.fail_got("physics.artificial_viscosity", "an object {alpha, beta, epsilon}", *av);
    r.mark_known("physics.artificial_viscosity");
    s.av_alpha = r.number("physics.artificial_viscosity.alpha", 0.1, 0, 10, "linear coefficient alpha");
    s.av_beta = r.number("physics.artificial_viscosity.beta", 0.0, 0, 10, "quadratic coefficient beta");
    s.av_eps = r.number("physics.artificial_viscosity.epsilon", 0.01, 1e-6, 1, "eta^2/h^2 regulariser");
  }

  // --- physics toolbox terms (docs/physics.md): each off unless its key is present -------------------
  const auto object_key = [&](const std::string& key, const std::string& expected) {
    if (!r.has(key)) return false;
    if (!r.raw(key)->is_object()) r.fail_got(key, expected, *r.raw(key));
    r.mark_known(key);
    return true;
  };
  if (object_key("physics.laminar_viscosity", "an object {nu [m^2/s]}")) {
    s.laminar_viscosity = true;
    s.nu = r.positive("physics.laminar_viscosity.nu", std::nullopt, "kinematic viscosity nu [m^2/s]");
  }
  s.body_force = r.vector("physics.body_force", d, std::vector<double>(d, 0.0), "body acceleration [m/s^2]");
  if (object_key("physics.xsph", "an object {epsilon}"))
    s.xsph_eps = r.number("physics.xsph.epsilon", 0.5, 0, 1, "XSPH epsilon in [0, 1]");
  if (object_key("physics.damping", "an object {mu [1/s], until [s]}")) {
    s.damping = true;
    s.damping_mu = r.number("physics.damping.mu", std::nullopt, 0, kInf, "damping rate mu [1/s]");
    s.damping_until = r.number("physics.damping.until", kInf, 0, kInf, "end of damping [s]");
  }
  if (object_key("physics.damping_zone", "an object {from [m], to [m], beta [1/s], profile}")) {
    // wave absorption at a flume's end (Altomare et al. 2017; physics/damping_zone.hpp)
    s.damping_zone = true;
    s.damping_zone_from = r.vector("physics.damping_zone.from", d, std::nullopt, "where the zone starts (no damping) [m]");
    s.damping_zone_to = r.vector("physics.damping_zone.to", d, std::nullopt, "where the damping is largest [m]");
    double len2 = 0;
    for (int a = 0; a < d; ++a) len2 += (s.damping_zone_to[a] - s.damping_zone_from[a]) * (s.damping_zone_to[a] - s.damping_zone_from[a]);
    if (!(len2 > 0)) r.fail("physics.damping_zone.to", "a point other than physics.damping_zone.from (the zone's length)");
    s.damping_zone_beta = r.number("physics.damping_zone.beta", 10.0, 0, 1e6, "largest relaxation rate [1/s]");
    s.damping_zone_profile = r.choice("physics.damping_zone.profile", "quadratic", {"quadratic", "linear"});
  }
  if (object_key("physics.gravity_ramp", "an object {duration [s]}"))
    s.gravity_ramp = r.positive("physics.gravity_ramp.duration", std::nullopt, "ramp duration T [s]");
  if (object_key("physics.density_diffusion", "an object {type, delta}")) {
    s.density_diffusion =
        r.choice("physics.density_diffusion.type", "molteni", {"none", "molteni", "fourtakas", "antuono"});
    s.diffusion_delta = r.number("physics.density_diffusion.delta", 0.1, 0, 1, "delta-SPH coefficient");
    if (s.density != "continuity" && s.density_diffusion != "none")
      r.fail("physics.density_diffusion", "physics.density = \"continuity\" (diffusion acts on the continuity equation)");
  }
  if (object_key("physics.riemann", "an object {eta}")) {
    // Zhang, Hu & Adams 2017: the Riemann solver's dissipation replaces AV and delta-SPH (physics/riemann.hpp)
    s.riemann = true;
    s.riemann_eta = r.number("physics.riemann.eta", 3.0, 0, 1e6, "slope of the low-dissipation limiter");
    if (s.artificial_viscosity)
      r.fail("physics.riemann", "no physics.artificial_viscosity beside it (the Riemann solver's dissipation replaces it)");
    if (s.density_diffusion != "none")
      r.fail("physics.riemann", "no physics.density_diffusion beside it (the Riemann solver diffuses density itself)");
    if (s.density != "continuity") r.fail("physics.riemann", "physics.density = \"continuity\"");
  }
  if (object_key("physics.tensile_instability", "an object {type, epsilon, n}")) {
    s.tensile = r.choice("physics.tensile_instability.type", "artificial_stress", {"none", "artificial_stress"});
    s.as_eps = r.number("physics.tensile_instability.epsilon", 0.2, 0, 10, "artificial stress epsilon");
    s.as_n = r.number("physics.tensile_instability.n", 4, 1, 16, "exponent n of (W/W(dx))^n");
  }

  if (object_key("physics.shifting", "an object {coefficient, velocity, tensile_R, tensile_n, free_surface, "
                                     "free_surface_threshold, max_shift}")) {
    s.shifting = true;
    s.shift_A = r.number("physics.shifting.coefficient", 2.0, 0, 100, "A in D = A h |v| dt");
    s.shift_velocity = r.choice("physics.shifting.velocity", "local", {"local", "max"});
    s.shift_R = r.number("physics.shifting.tensile_R", 0.2, 0, 10, "R of 1 + R (W/W(dx))^n (Sun 2017)");
    s.shift_n = int(r.integer("physics.shifting.tensile_n", 4, 1, 16));
    s.shift_free_surface = r.choice("physics.shifting.free_surface", "zero", {"none", "zero", "tangential"});
    s.shift_fs_threshold = r.number("physics.shifting.free_surface_threshold", d == 2 ? 1.5 : 2.75, 0, d,
                                    "div r below which a particle is at the free surface");
    if (s.shift_free_surface == "tangential")
      s.shift_near_threshold = r.number("physics.shifting.near_surface_threshold", 0.5 * (s.shift_fs_threshold + d),
                                        s.shift_fs_threshold, d, "div r below which only tangential shifts are kept");
    s.shift_max = r.number("physics.shifting.max_shift", 0.1, 1e-6, 0.5, "cap on |dr| per step in units of dx");
  }

  s.boundary_model =
      r.choice("boundary.model", "repulsive", {"repulsive", "dynamic", "dummy_adami", "soft_repulsive", "mdbc"});
  if (s.boundary_model == "dummy_adami" || s.boundary_model == "soft_repulsive" || s.boundary_model == "mdbc")
    s.wall_slip = r.choice("boundary.slip", "no_slip", {"no_slip", "free_slip"});
  if (s.boundary_model == "mdbc")
    s.mdbc_extrapolation = r.choice("boundary.mdbc.extrapolation", "gradient", {"gradient", "hydrostatic"});
  if (s.boundary_model == "soft_repulsive")
    s.soft_wall_coef = r.positive("boundary.soft_repulsive.coefficient", 0.01, "force scale / c0^2 (Chalk 2020: 0.01)");
  {
    const double u2 = std::max(2 * g * fluid_height, 1e-12);
    const json* D = r.raw("boundary.repulsive.D");
    if (D && D->is_string() && D->get<std::string>() == "auto") {
      r.text("boundary.repulsive.D", "auto");
      s.wall_D = u2;
    } else {
      s.wall_D = r.number("boundary.repulsive.D", u2, 0, kInf, "wall strength D [m^2/s^2] or \"auto\" (2 g H)");
    }
    s.wall_r0 = s.spacing * r.positive("boundary.repulsive.r0_over_dx", 1.0, "r0 / dx");
    s.wall_n1 = int(r.integer("boundary.repulsive.n1", 12, 1, 64));
    s.wall_n2 = int(r.integer("boundary.repulsive.n2", 4, 1, 64));
    if (s.wall_n2 >= s.wall_n1) r.fail("boundary.repulsive.n2", "n2 < n1");
  }

  s.integrator = r.choice("integrator.type", "verlet",
                          {"verlet", "variational", "symplectic_euler", "rk4", "predictor_corrector",
                           "verlet_dsph"});
  if (s.integrator == "verlet_dsph") {
    s.euler_every = int(r.integer("integrator.euler_every", 40, 1, 1000000));
    if (s.density != "continuity")
      r.fail("physics.density", "\"continuity\" with integrator.type \"verlet_dsph\" (one fused sweep per step)");
    // Zhang et al.'s continuity dissipation is a diffusion; the leapfrog density update rho^{n+1} =
    // rho^{n-1} + 2 dt drho^n amplifies a diffusion's parasitic mode every step, which an Euler step every
    // 40 no longer catches at its strength (a dam break failed at step 21; test Riemann.VerletDsph...)
    if (s.riemann)
      r.fail("physics.riemann", "an integrator.type other than \"verlet_dsph\" (verlet, symplectic_euler, "
                                "predictor_corrector, rk4 or variational): its two-level density update amplifies "
                                "the Riemann solver's density dissipation (docs/integrators.md)");
  }
  if (r.has("integrator.dt")) s.dt = r.positive("integrator.dt", std::nullopt, "time step dt [s]");
  if (r.has("integrator.cfl")) s.cfl = r.number("integrator.cfl", std::nullopt, 1e-6, 1.0, "CFL number");
  if (s.shifting && s.integrator != "verlet" && s.integrator != "symplectic_euler" &&
      s.integrator != "predictor_corrector" && s.integrator != "rk4" && s.integrator != "verlet_dsph")
    r.fail("physics.shifting", "an explicit integrator that applies it (verlet, symplectic_euler, predictor_corrector, "
                               "rk4, verlet_dsph); integrator.type \"" + s.integrator + "\" does not shift particles");
  if (!s.dt && !s.cfl) r.fail("integrator.dt", "integrator.dt [s] or integrator.cfl (one of them is required)");
  if (s.dt && s.cfl) r.fail("integrator.cfl", "only one of integrator.dt and integrator.cfl");
  if (s.has_rigid_bodies() && s.integrator != "verlet" && s.integrator != "symplectic_euler" &&
      s.integrator != "verlet_dsph" && s.integrator != "variational")
    r.fail_got("integrator.type", "\"symplectic_euler\", \"verlet\", \"verlet_dsph\" or \"variational\" with rigid "
                                  "bodies (the bodies are not advanced inside the other schemes' stages yet; "
                                  "docs/bodies.md)", json(s.integrator));
  s.alpha = r.number("integrator.alpha", s.integrator == "variational" ? 0.5 : 1.0, 0, 1, "alpha in [0, 1]");
  // the variational midpoints evaluate the walls' state only for these two models (docs/variational.md)
  if (s.has_rigid_bodies() && s.integrator == "variational" && s.alpha < 1 &&
      s.boundary_model != "repulsive" &&
      s.boundary_model != "dynamic")
    r.fail_got("boundary.model", "\"repulsive\" or \"dynamic\" for rigid bodies with integrator.type "
                                 "\"variational\" (its generalised midpoints do not extrapolate dummy or mDBC wall "
                                 "pressures; docs/bodies.md)", json(s.boundary_model));
  s.fp_tolerance = r.positive("integrator.fixed_point.tolerance", 1e-6, "tolerance relative to dx");
  if (r.has("integrator.fixed_point.absolute_tolerance"))
    s.fp_absolute_tolerance = r.positive("integrator.fixed_point.absolute_tolerance", std::nullopt, "tolerance [m]");
  s.fp_max_iterations = int(r.integer("integrator.fixed_point.max_iterations", 50, 1, 100000));
  s.fp_on_failure = r.choice("integrator.fixed_point.on_failure", "fail", {"fail", "halve_dt"});

  // --- time integrators and kernel corrections (docs/integrators.md) ---
  {
    const double C = s.cfl ? *s.cfl : 0.2;
    if (r.has("integrator.cfl_criteria")) {
      if (!r.raw("integrator.cfl_criteria")->is_object())
        r.fail_got("integrator.cfl_criteria", "an object {acoustic, force, viscous}", *r.raw("integrator.cfl_criteria"));
      if (!s.cfl) r.fail("integrator.cfl", "integrator.cfl when integrator.cfl_criteria is given");
      r.mark_known("integrator.cfl_criteria");
    }
    s.cfl_acoustic = r.number("integrator.cfl_criteria.acoustic", C, 1e-6, 10, "C_a in C_a h / (c0 + v_max)");
    s.cfl_force = r.number("integrator.cfl_criteria.force", C, 1e-6, 10, "C_f in C_f sqrt(h / a_max)");
    s.cfl_viscous = r.number("integrator.cfl_criteria.viscous", 0.125, 1e-6, 10, "C_v in C_v h^2 / nu");
    if (r.has("physics.shepard_reinit")) {
      const json* sh = r.raw("physics.shepard_reinit");
      if (!sh->is_object()) r.fail_got("physics.shepard_reinit", "an object {\"every\": N steps}", *sh);
      r.mark_known("physics.shepard_reinit");
      s.shepard_reinit_every = int(r.integer("physics.shepard_reinit.every", 20, 1, 1000000000));
      if (s.density != "continuity")
        r.fail("physics.shepard_reinit", "physics.density \"continuity\" (summation densities are not state)");
    }
  }

  s.t_end = r.positive("time.end", std::nullopt, "end time [s]");
  s.output_every = r.positive("output.every", s.t_end / 50, "seconds between frames");
  s.output_fields = r.strings("output.fields", std::vector<std::string>{"velocity", "density", "pressure", "mass",
                                                                        "id", "kind", "normal", "body"});
  s.output_precision = r.choice("output.precision", "float32", {"float32", "float64"});
  s.output_static_boundary = r.choice("output.static_boundary", "every_frame", {"every_frame", "once"});
  s.checkpoint_every = r.number("checkpoint.every", 0.0, 0, kInf, "simulated seconds between checkpoints");
  s.checkpoint_wall_minutes = r.number("checkpoint.wall_minutes", 0.0, 0, kInf, "wall-clock minutes");
  s.checkpoint_every_steps = r.integer("checkpoint.every_steps", 0, 0, 1000000000000L);
  s.probes_every = r.number("output.probes_every", s.output_every / 10, 0, kInf,
                            "simulated seconds between probes.csv rows (0 = every step)");
  s.probes = r.subtree("probes", json::array());
  if (!s.probes.is_array()) r.fail_got("probes", "a list of probes", s.probes);
  s.health = parse_health(r);
  s.log_every_steps = int(r.integer("log.every_steps", 0, 0, 1000000000));
  s.rebalance_threshold = r.number("parallel.rebalance_threshold", 1.15, 1.0, 1e6,
                                   "slowest rank's busy time over the mean that triggers a repartition");
  s.rebalance_check_every = r.integer("parallel.rebalance_check_every", 50, 0, 1000000000000L);
  s.rebalance_every = r.integer("parallel.rebalance_every", 0, 0, 1000000000000L);
  s.fluid_weight = int(r.integer("parallel.weights.fluid", 4, 1, 1000000));
  s.boundary_weight = int(r.integer("parallel.weights.boundary", 1, 0, 1000000));
  // "cost": refit the weights from the ranks' busy times at every balance check (parallel/cost_fit.hpp)
  s.weights_by_cost = r.choice("parallel.weights.mode", "count", {"count", "cost"}) == "cost";
  // where the steps run (docs/gpu.md): the OpenMP host loops, a CUDA device, or the CUDA backend's
  // loops through a host launch (tests, debugging)
  s.device = r.choice("execution.device", "cpu", {"cpu", "cuda", "cuda_emulation"});

  r.check_unknown();
  s.setup_supplied = r.supplied();
  s.resolved = r.resolved();
  (void)check_sanity(s);  // errors stop here; the commands ask again for the warnings
  return s;
}

Scene parse_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
  return parse_scene_json(read_json_file(file), file, overrides);
}

}  // namespace varsph::scene
