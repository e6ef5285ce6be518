#pragma once
// Open boundaries: inlets and outlets as buffer zones (scene `open_boundaries`, docs/open_boundaries.md).
//
// Scheme: the buffer zones of Tafuni, Dominguez, Vacondio & Crespo 2018, "A versatile algorithm for the
// treatment of open boundary conditions in Smoothed particle hydrodynamics GPU models", Comput. Methods
// Appl. Mech. Engrg. 342:604-624 (the inlet/outlet of DualSPHysics), chosen because a DualSPHysics user
// moving a case expects its behaviour, and because its ingredient, first-order corrected interpolation at
// a ghost node (Liu & Liu 2006), is already varsph's (physics/corrected_interpolation.hpp, mDBC, probes).
//  - A zone is a box beside the fluid, its interface the face its `direction` (a unit axis vector from
//    the zone into the fluid) points to; its depth along the direction must cover the kernel support.
//    Or an oblique plane zone: an interface rectangle of any orientation (centre, unit normal `direction`,
//    widths along its tangents) swept `depth` against the normal, with its own lattice on planes parallel
//    to the interface; the same scheme along the normal (distance n.(x - c), ghost node x - 2 s n, copies
//    one depth upstream along -n). In 3D its interface may be a polygon or a disc instead of the rectangle:
//    the lattice of the bounding rectangle, only the nodes inside the polygon / disc (a circular pipe inlet,
//    with the Hagen-Poiseuille profile u = peak (1 - r^2 / R^2)).
//  - Buffer particles are fluid particles (kind 0) tagged with their zone in the registered field
//    `open_zone` (-1: not a buffer). They take part in every neighbour sum as fluid, but their state is
//    imposed: each moves with the velocity it had at the start of the step (x = x0 + dt v0, Tafuni
//    sec. 3.1), placed there in the step's sort (place_buffers) so the grid is that of the final
//    positions, and after the step gets
//      inlet:  the prescribed velocity u(x, t) along the direction (uniform, 2D parabolic, or a time
//              series), and the pressure of its ghost node x_g = x - 2 s n (its mirror image across the
//              interface, s < 0 its signed distance; the first-order fit's value p_g) carried along n with the
//              buffer's own momentum balance, p = p_g + (x - x_g) . n dp/dn, dp/dn = rho0 (g - du/dt) . n +
//              mu lap u (Gresho & Sani 1987; Tafuni's eq. 20, the fluid's own gradient, ran away next to
//              no-slip walls: issue 32), or the density of a prescribed pressure;
//      outlet: the velocity of its ghost node (zero gradient, Tafuni eq. 21) and the density of the
//              prescribed pressure (default 0 Pa), or the extrapolated one.
//  - Transitions, in storage order after every step: an inlet buffer particle that crossed the interface
//    (s >= 0) becomes fluid and a copy of it, one zone depth upstream, takes its place in the buffer (the
//    lattice column is kept); a fluid particle inside an outlet zone becomes an outlet buffer particle;
//    one that moved back across the interface becomes fluid again; a buffer particle beyond the zone's
//    outer face (s < -depth) is removed; a fluid particle that flows back into an inlet zone (near its
//    walls, where the inflow vanishes) is removed and counted as outflow. Creation and removal are store operations (ParticleStore::
//    append_copies / compact, ids from the run's counter: Simulation::create_particles), followed by
//    the sort; nothing is allocated per step beyond the store's doubling growth.
//  - Mass balance (Simulation::flow()): mass enters when a buffer particle becomes fluid, leaves when a
//    fluid particle becomes a buffer particle or is removed by a health rule.
// Everything is deterministic and independent of the thread count (per-particle writes, serial
// transitions). On several MPI ranks the same bits as one process: the transitions are keyed by the particles'
// order tags (the serial storage order), so the flows are summed and created particles numbered (ids, and
// tags that sort them after every existing particle) as one process does; a buffer particle whose ghost node
// lies in another rank's cells has its fit computed there (all its neighbours are there, in the serial order)
// and sent back. Not available on the device (refused at start, naming the key).
#include <array>
#include <cstdint>
#include <vector>

#include "scene/scene.hpp"
#include "sim/simulation.hpp"

namespace varsph {

template <int D>
class OpenBoundaries {
 public:
  // Registers the fields `open_zone` (checkpointed, exported), `open_x0` and `open_v0` (scratch).
  OpenBoundaries(const scene::Scene& s, ParticleStore& store);

  // Before the first sort: validates the zones against the built particles and the kernel support
  // (InputError naming the zone and key: a zone overlapping a wall, thinner than the support, an integrator
  // the buffer update is not written for), replaces the fluid inside the zones by their lattices.
  void setup(Simulation<D>& sim, Real support);
  // After the first sort: the buffer particles' velocity, density and pressure for t = 0.
  void initial_values(Simulation<D>& sim) { impose(sim); }
  // Around each step (Simulation::advance).
  void before_step(Simulation<D>& sim);
  // Inside a step, from Simulation::sort_and_bin() before it bins (the integrator's drift): the buffer
  // particles' positions x0 + dt v0, so the grid, the density update after the drift and the next step
  // see them where they are. Outside a step (the first sort, a restart) it does nothing.
  void place_buffers(Simulation<D>& sim);
  void after_step(Simulation<D>& sim);
  // A step abandoned (a blow-up replay, a restart): the next sort places nothing.
  void abandon_step() { stepping_ = placed_ = false; }

  std::size_t buffer_count() const { return buffers_; }
  // Wall time spent here since the start (bench/open): the transitions with creation, removal and the sort
  // after them, and the buffer update (kinematics, extrapolation). Timings are for benchmarks, never tests.
  double transition_seconds() const { return transition_seconds_; }
  double impose_seconds() const { return impose_seconds_; }

 private:
  struct Zone {
    const scene::OpenZoneSpec* spec;
    bool inlet;
    int axis;
    Real sign;         // direction = sign e_axis
    Real face;         // interface coordinate on the axis
    Real depth;        // extent along the axis [m]
    Vec<D> lo, hi;     // the box
    Real rho_prescribed;
    // free-surface inlet (water_level): the vertical axis D - 1; |g_z| for the hydrostatic density
    bool surface = false;
    Real gz = 0;
    // an oblique plane zone (scene keys center/depth/width): the unit normal n into the fluid, the interface's
    // centre c, the unit tangents and half-widths; lo/hi are then its bounding box. Its lattice: points
    // c - (i + 1/2) dx n + sum_k ((j_k + 1/2) dx - hw_k) t_k, on planes parallel to the interface.
    bool oblique = false;
    Vec<D> n = Vec<D>::Zero(), c = Vec<D>::Zero();
    std::array<Vec<D>, D - 1> t{};
    std::array<Real, D - 1> hw{};
    // 3D: the interface a polygon (shape 1: vertices (a, b) along t_0, t_1 about c) or a disc (shape 2: radius R
    // about c) instead of the rectangle (shape 0). Their lattice is that of the in-plane bounding rectangle, of
    // sides ext_k from its lower corner -hw_k (so lattice_point is the rectangle's formula), filtered by the
    // polygon's or the disc's inside test (in_plane).
    int shape = 0;
    std::vector<std::array<double, 2>> poly;
    double radius = 0;
    std::array<Real, D - 1> ext{};
  };
  // a polygon or disc zone: the in-plane point of x inside the interface (strict: by more than tol from its
  // edge; else on or inside it)
  bool in_plane(const Zone& z, const Vec<D>& x, Real tol, bool strict) const;
  // an oblique zone's lattice point of index (i along -n, j_k along t_k)
  Vec<D> lattice_point(const Zone& z, const std::array<long, D>& idx, double dx) const;
  // the zone's lattice counts: axis-aligned, per axis; oblique, along -n first, then along each tangent
  std::array<long, D> lattice_cells(const Zone& z, double dx) const;
  // strictly inside the zone (its box, or its oblique extent), by tol
  bool inside(const Zone& z, const Vec<D>& x, Real tol) const;
  // a free-surface inlet's buffer particle at x lies below the water level at time t (its lattice row is wet)
  bool wet(const Zone& z, const Vec<D>& x, double t) const {
    return !z.surface || double(x[D - 1]) < z.spec->level_at(t);
  }
  // A time-varying level that rose during the step [t0, t1]: the zone's lattice rows that became wet get
  // buffer particles, appended after the step's `created_before` copies (ids, and on several ranks order tags,
  // after theirs). Every rank lists the same rows; on several ranks the rank that owns one process's source
  // particle (the first fluid particle in the serial storage order: the smallest order tag) creates them all,
  // copies of that particle as in one process, and the rebin moves them to their owners. Returns the number.
  std::size_t fill_risen_rows(Simulation<D>& sim, double t0, double t1, std::int64_t created_before);
  // Signed distance from the interface along the direction (< 0 inside the zone's depth).
  Real distance(const Zone& z, const Vec<D>& x) const {
    return z.oblique ? z.n.dot(x - z.c) : z.sign * (x[z.axis] - z.face);
  }
  bool beside(const Zone& z, const Vec<D>& x) const;  // within the box's extent across the direction
  // the unit direction into the fluid
  Vec<D> normal(const Zone& z) const {
    if (z.oblique) return z.n;
    Vec<D> n = Vec<D>::Zero();
    n[z.axis] = z.sign;
    return n;
  }
  // An inlet buffer particle's pressure gradient along the direction from its own momentum balance with the
  // prescribed velocity: rho0 (g - du/dt) . n + mu lap u [Pa/m] (the pressure extrapolated from the ghost node).
  double normal_gradient(const Zone& z, const Vec<D>& x, double t) const;
  Vec<D> inflow(const Zone& z, const Vec<D>& x, double t) const;
  // InputError naming the first outlet that no inlet reaches through the domain (walls in between).
  void check_outlets_reachable(Simulation<D>& sim) const;
  // Velocity, density and pressure of every buffer particle from the zones' conditions (grid valid).
  void impose(Simulation<D>& sim);

  const scene::Scene& scene_;
  std::vector<Zone> zones_;
  Field<std::int32_t>* zone_;
  Field<Vec<D>>* x0_;
  Field<Vec<D>>* v0_;
  std::vector<std::uint32_t> created_src_, removed_, kept_, buffer_idx_;
  std::vector<std::int32_t> created_zone_;
  std::vector<std::int64_t> order_;  // each created particle's place in this step's serial creation order
  std::size_t buffers_ = 0;
  bool stepping_ = false;  // between before_step and after_step
  bool placed_ = false;    // place_buffers ran in this step (else after_step places them and rebins)
  double step_t0_ = 0;     // the time at the step's start (a varying water level: the rows wet then)
  std::vector<Vec<D>> row_pts_;
  double transition_seconds_ = 0, impose_seconds_ = 0;
};

}  // namespace varsph
