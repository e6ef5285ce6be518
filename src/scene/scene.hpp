#pragma once
// A scene parsed and validated into plain structs (SI units). Every optional key has its default here
// and in docs/scene.md; parse_scene() fills `resolved` with every parameter actually used.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "kernels/kernel_type.hpp"

namespace varsph::scene {

// A rigid body moved by the fluid (kind "rigid"; src/bodies/, docs/bodies.md). Mass properties come
// from a uniform solid `density` over the body's shape or mesh, or are given (`mass`, `center_of_mass`,
// `inertia`). Vectors have 3 components in 3D; in 2D rotation is about z and masses are per metre.
struct RigidSpec {
  double density = 0;                      // solid density [kg/m^3] (0: mass given instead)
  double mass = 0;                         // [kg] (2D: kg/m); 0: from density
  std::vector<double> center_of_mass;      // given centre of mass [m] (empty: of the uniform solid)
  std::vector<double> inertia;             // given, about the centre of mass: 2D {Izz}; 3D {xx,yy,zz,xy,xz,yz}
  std::vector<double> angular_velocity;    // initial [rad/s]: 2D {wz}, 3D {wx,wy,wz}
  std::string constraint = "free";         // "free" | "hinge" | "fixed_point"
  std::vector<double> pivot;               // hinge / fixed point: a point on the axis [m]
  std::vector<double> axis;                // hinge (3D): axis direction (2D: z)
  std::vector<bool> lock_translation;      // per axis
  std::vector<bool> lock_rotation;         // 2D: {z}; 3D: {x, y, z} (world axes)
  std::vector<double> cylinder_axis;       // shape "cylinder" (3D): axis direction
  double cylinder_length = 0;              // shape "cylinder" (3D): length [m]
};

// A linear spring-damper from a point of a rigid body to a fixed anchor or to a point of another body.
struct MooringSpec {
  int body = -1;                   // scene body index (a rigid body)
  std::vector<double> point;       // attachment on the body at t = 0 [m]
  int anchor_body = -1;            // -1: fixed anchor
  std::vector<double> anchor;      // fixed anchor, or the attachment on anchor_body at t = 0 [m]
  double stiffness = 0;            // [N/m] (2D: N/m per metre)
  double damping = 0;              // [N s/m]
  double rest_length = -1;         // [m]; < 0: the initial distance
  bool slack = true;               // a line: no force when shorter than its rest length
};

// Contact between rigid bodies and any other boundary body (sim: bodies/contact.hpp).
struct ContactSpec {
  bool enabled = true;
  double distance = 1.0;           // contact distance between boundary particles [dx]
  double stiffness = 0;            // [N/m per particle pair] (0: auto = rho0 c0^2 dx^(d-2))
  double restitution = 0.5;        // normal restitution coefficient of a particle pair
};

struct BodySpec {
  std::string kind;   // "fluid" | "boundary" | "rigid"
  std::string shape;  // "box" | "tank" | "sphere" | "cylinder" | "points" | "mesh"
  std::vector<double> min, max;           // box / tank corners [m]
  std::vector<double> center;             // sphere / disc centre [m]
  double radius = 0;                      // [m]
  std::vector<std::vector<double>> points;      // shape "points": positions [m]
  std::vector<std::vector<double>> velocities;  // shape "points": per-point velocities [m/s]
  std::vector<double> pressures;                // shape "points": per-point initial pressures [Pa]
  std::vector<double> velocity;           // initial velocity of the whole body [m/s]
  std::vector<bool> open;                 // tank: per axis and side {min0,max0,min1,max1,...} left open
  int layers = 1;                         // boundary particle layers (tank, box surface, mesh)
  std::string initial_pressure = "zero";  // fluid: "zero" | "hydrostatic"
  double free_surface = 0;                // hydrostatic: level of the free surface [m] (default body top)
  nlohmann::json mesh;                    // shape "mesh": the body's mesh keys, for the geometry module
  nlohmann::json motion;                  // boundary: prescribed motion (sim/boundary_motion.hpp), null if fixed
  RigidSpec rigid;                        // kind "rigid" only
};

// health.* (sim/health.hpp, docs/scene.md "Health"): what happens to a fluid particle that leaves the
// states the weakly-compressible model describes, and which events are a blow-up (exit 3).
struct HealthSpec {
  std::string on_violation = "remove";  // "remove" (counted) | "stop" (exit 3, the strict behaviour)
  double max_density_error = 0.3;       // |rho/rho0 - 1| bound (DualSPHysics RhopOut default 700-1300 kg/m^3)
  double max_mach = 1.0;                // |v| / c0 bound
  double max_removed_fraction = 0.01;   // of the initial fluid particles, within removal_window steps
  long removal_window = 20;             // [steps]
  double max_removed_total = 0.05;      // of the initial fluid particles, over the whole run
  double max_energy_growth = 0.1;       // of the energy scale (sim/health.hpp); 0 = off
};

// An open boundary (top-level `open_boundaries`; sim/open_boundaries.hpp, docs/open_boundaries.md): a box
// of buffer particles beside the fluid, its interface the box face that `direction` points to. Buffer
// scheme of Tafuni et al. 2018 (ghost nodes mirrored into the fluid, first-order corrected interpolation).
struct OpenZoneSpec {
  std::string name;
  std::string kind;                 // "inlet" | "outlet"
  std::vector<double> min, max;     // the zone's box [m]; faces on the fluid's lattice lines
  std::vector<double> direction;    // unit axis vector from the zone into the fluid (inlets and outlets)
  int axis = 0;                     // the axis of `direction`
  double sign = 1;                  // its sign (+1 or -1)
  // An oblique plane zone (keys `center`, `depth`, `width`, 3D `tangent` instead of `min`/`max`): the interface
  // is the rectangle through `center` normal to `direction` (normalised; any orientation), the zone reaches
  // `depth` against it. Tangents: 2D (-n_y, n_x); 3D `tangent` (normalised, normal to n) and n x tangent.
  // min/max then hold the zone's bounding box. Axis-aligned zones (min/max) never take this path.
  bool oblique = false;
  std::vector<double> center;                // a point on the interface: the centre of the zone's face [m]
  double depth = 0;                          // extent against `direction` [m], a multiple of the spacing
  std::vector<double> width;                 // full widths along the tangents [m] (D - 1 of them)
  std::vector<std::vector<double>> tangents;  // D - 1 unit vectors in the interface plane
  // 3D only: the interface a polygon (`polygon`, vertices [a, b] in metres along tangents[0] and tangents[1]
  // about `center`) or a disc (`radius` about `center`) instead of the `width` rectangle. `width` then holds the
  // in-plane bounding rectangle's sides and `plane_lo` its lower corner (a, b): the zone's lattice is that
  // rectangle's, the inside test the polygon's or the disc's.
  std::string interface = "rectangle";            // "rectangle" | "polygon" | "disc"
  std::vector<std::array<double, 2>> polygon;     // >= 3 vertices, simple (not self-intersecting), area > 0
  double radius = 0;                              // the disc's radius [m]
  std::vector<double> plane_lo;                   // polygon/disc: the bounding rectangle's lower corner (a, b)
  // inlet velocity along `direction`: "uniform" (value), "parabolic" (2D, across the zone: peak; with a
  // water level the open-channel half parabola, peak at the surface; on a 3D disc the Hagen-Poiseuille
  // profile peak (1 - r^2 / R^2) about `center`), "log_law" (water level only: depth-mean
  // value, roughness z0), "file"
  std::string profile = "uniform";
  double speed = 0;                 // uniform: speed; parabolic: peak speed; log_law: depth-mean speed [m/s]
  double roughness = 0;             // log_law: z0 [m]
  std::vector<double> series_t, series_u;  // profile "file": times [s] (strictly increasing) and speeds [m/s]
  double ramp = 0;                  // velocity.ramp: the inflow rises as (1 - cos(pi t / ramp)) / 2 over this [s]
  bool pressure_extrapolated = true;  // inlet default; outlets default to a prescribed pressure
  double pressure = 0;              // prescribed pressure [Pa] (when not extrapolated)
  // The inflow speed at time t (profile "file": linear in time, held beyond the ends), times the ramp [m/s].
  double speed_at(double t) const;
  // Free-surface inlet (`water_level`, DualSPHysics' imposed zsurf, Tafuni et al. 2018): buffer particles only
  // below the level on the vertical axis (the last), fixed or a time series (linear, held beyond the ends).
  bool surface = false;
  double level = 0;                        // the fixed level [m] (a coordinate on the vertical axis)
  std::vector<double> level_t, level_z;    // water_level.file: times [s] (strictly increasing), levels [m]
  bool hydrostatic = false;                // pressure "hydrostatic": p = p_b + rho0 |g_z| (level - z)
  double level_at(double t) const;
  bool level_varies() const { return !level_t.empty(); }
};

struct Scene {
  std::filesystem::path file;
  nlohmann::json resolved;  // every parameter with its value (defaults filled in)
  // top-level `setup` (issue 35): "engineering" (default) or "paper", the defaults of the method keys a scene
  // leaves out (scene/parse_scene.cpp apply_setup, docs/scene.md "Set-up"), and the keys it filled in
  std::string setup = "engineering";
  std::vector<std::string> setup_supplied;

  std::string name;
  int dimension = 2;
  std::vector<double> domain_min, domain_max;
  std::vector<bool> periodic;
  std::string neighbor_search = "cell";  // "cell" (bounded grid) | "hash" (unbounded)

  double spacing = 0;  // particles.spacing dx [m]
  double min_boundary_distance = 0;  // fluid particles closer than this to a boundary particle are removed [m]

  kernels::KernelType kernel = kernels::KernelType::Gaussian;
  double h = 0;         // smoothing length [m]
  double kernel_l = 9.47;
  bool kernel_tabulated = true;

  double rho0 = 1000;
  double c0 = 0;               // resolved speed of sound [m/s]
  double background_pressure = 0;  // fluid.background_pressure [Pa]
  std::string c0_rule;         // how c0 was obtained
  // fluid.reference_height / reference_speed as the scene names them (-1: not named): the c0 "auto" rule's
  // scales, and with a given c0 the scene check's flow scales (scene/sanity.cpp, docs/scene.md)
  double reference_height = -1;  // [m]
  double reference_speed = -1;   // [m/s]
  std::vector<double> gravity;

  std::vector<BodySpec> bodies;
  std::vector<OpenZoneSpec> open_boundaries;  // top-level `open_boundaries` (empty: closed domain)
  std::vector<MooringSpec> moorings;  // rigid bodies' moorings (top-level `moorings`)
  ContactSpec contact;                // rigid bodies' contact (top-level `contact`)
  bool has_rigid_bodies() const {
    for (const auto& b : bodies)
      if (b.kind == "rigid") return true;
    return false;
  }

  // physics.*
  std::string density = "continuity";  // "continuity" | "summation"
  bool riemann = false;       // physics.riemann (Zhang, Hu & Adams 2017)
  double riemann_eta = 3;     // its low-dissipation limiter slope
  bool artificial_viscosity = false;
  double av_alpha = 0, av_beta = 0, av_eps = 0.01;

  // physics.* toolbox terms (docs/physics.md), each off unless named
  bool laminar_viscosity = false;
  double nu = 0;                         // physics.laminar_viscosity.nu [m^2/s]
  std::vector<double> body_force;        // physics.body_force [m/s^2] (default zero)
  double xsph_eps = 0;                   // physics.xsph.epsilon [-] (0 = off)
  bool damping = false;
  double damping_mu = 0, damping_until = 0;  // physics.damping.{mu [1/s], until [s]}
  // physics.damping_zone (physics/damping_zone.hpp): fluid velocity relaxed towards zero beyond `from`
  bool damping_zone = false;
  std::vector<double> damping_zone_from, damping_zone_to;  // [m]: no damping at `from`, the most at `to`
  double damping_zone_beta = 10;                           // [1/s]
  std::string damping_zone_profile = "quadratic";          // quadratic | linear
  double gravity_ramp = 0;               // physics.gravity_ramp.duration [s] (0 = off)
  std::string density_diffusion = "none";  // physics.density_diffusion.type: none | molteni | fourtakas | antuono
  double diffusion_delta = 0.1;
  std::string tensile = "none";          // physics.tensile_instability.type: none | artificial_stress
  double as_eps = 0.2, as_n = 4;
  // physics.shifting (particle shifting, physics/shifting.hpp); off unless named
  bool shifting = false;
  double shift_A = 2;                      // physics.shifting.coefficient [-]
  std::string shift_velocity = "local";    // physics.shifting.velocity: local | max
  double shift_R = 0.2;                    // physics.shifting.tensile_R [-]
  int shift_n = 4;                         // physics.shifting.tensile_n [-]
  std::string shift_free_surface = "zero";  // physics.shifting.free_surface: none | zero | tangential
  double shift_near_threshold = 1.75;      // physics.shifting.near_surface_threshold (tangential band)
  double shift_fs_threshold = 1.5;         // physics.shifting.free_surface_threshold [-] (div r)
  double shift_max = 0.1;                  // physics.shifting.max_shift [dx]

  // boundary.*
  std::string boundary_model = "repulsive";  // "repulsive" | "dynamic" | "dummy_adami" | "soft_repulsive" | "mdbc"
  std::string mdbc_extrapolation = "gradient";  // mdbc: "gradient" (English 2022) | "hydrostatic"
  double wall_D = 0, wall_r0 = 0;
  int wall_n1 = 12, wall_n2 = 4;
  std::string wall_slip = "no_slip";  // boundary.slip (dummy_adami, soft_repulsive): no_slip | free_slip
  double soft_wall_coef = 0.01;       // boundary.soft_repulsive.coefficient (force scale / c0^2)

  // integrator.*
  std::string integrator = "verlet";
  std::optional<double> dt, cfl;
  double alpha = 1.0;
  double fp_tolerance = 1e-6;  // relative to dx
  std::optional<double> fp_absolute_tolerance;  // [m], the paper's epsilon
  int fp_max_iterations = 50;
  std::string fp_on_failure = "fail";
  int euler_every = 40;  // integrator.euler_every (verlet_dsph): an Euler step every N steps

  double t_end = 0;
  double output_every = 0;
  std::vector<std::string> output_fields;
  std::string output_precision = "float32";
  // "every_frame": every frame holds every particle (CONTRACT.md); "once": the static walls go to a file of
  // their own, written at the first frame and again only when their number changes (issue 35)
  std::string output_static_boundary = "every_frame";
  double checkpoint_every = 0;  // [s] simulated, 0 = only at end
  double checkpoint_wall_minutes = 0;
  long checkpoint_every_steps = 0;  // steps between checkpoints, 0 = off
  double probes_every = 0;      // [s] simulated between probes.csv rows (output.probes_every)
  nlohmann::json probes;        // list, validated by the probes module
  HealthSpec health;            // health.*
  int log_every_steps = 0;

  // --- time integrators and kernel corrections (docs/integrators.md) ---
  // CFL criteria, each with its own coefficient (dimensionless); dt = min of the three limits:
  // acoustic C_a h / (c0 + v_max), force C_f sqrt(h / a_max), viscous C_v h^2 / nu.
  double cfl_acoustic = 0.2;  // integrator.cfl_criteria.acoustic (default integrator.cfl, else 0.2)
  double cfl_force = 0.2;     // integrator.cfl_criteria.force    (default integrator.cfl, else 0.2)
  double cfl_viscous = 0.125; // integrator.cfl_criteria.viscous  (Morris 1997)
  int shepard_reinit_every = 0;  // physics.shepard_reinit.every [steps], 0 = off

  // --- distributed runs (docs/parallel.md; ignored in one process, may change on restart) ---
  double rebalance_threshold = 1.15;  // parallel.rebalance_threshold: slowest rank's busy time / mean
  long rebalance_check_every = 50;    // parallel.rebalance_check_every [steps], 0 = never
  long rebalance_every = 0;           // parallel.rebalance_every [steps]: repartition regardless, 0 = off
  int fluid_weight = 4;               // parallel.weights.fluid: partition weight of a fluid particle
  int boundary_weight = 1;            // parallel.weights.boundary
  bool weights_by_cost = false;       // parallel.weights.mode = "cost" (parallel/cost_fit.hpp)
  std::string device = "cpu";  // execution.device: cpu | cuda | cuda_emulation (docs/gpu.md)
};

// Parses and validates a scene file with --set overrides applied first (InputError on any problem).
Scene parse_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});
// Same from an already-loaded JSON (tests, checkpoints). `file` is used in messages and for relative paths.
Scene parse_scene_json(nlohmann::json root, const std::filesystem::path& file,
                       const std::vector<std::string>& overrides = {});

}  // namespace varsph::scene
