#include "sim/build_particles.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "core/errors.hpp"
#include "neighbors/neighbor_grid.hpp"
#include "sim/mesh_bodies.hpp"
#include "sim/particle_budget.hpp"

namespace varsph {
namespace {

template <int D>
using Pts = std::vector<Vec<D>>;

// Number of lattice cells of size dx that fit in a length (tolerant to round-off: 0.145/0.005 = 29).
long cells_in(double len, double dx) { return long(std::floor(len / dx + 1e-6)); }

// Cell-centred lattice points of the box [lo, lo + n dx] (seed section 6: 29 x 58 particles).
template <int D, class F>
void for_each_lattice_point(const std::array<long, D>& first, const std::array<long, D>& last,
                            const Vec<D>& origin, double dx, F&& f) {
  std::array<long, D> i = first;
  while (true) {
    Vec<D> p;
    for (int a = 0; a < D; ++a) p[a] = origin[a] + Real((double(i[a]) + 0.5) * dx);
    f(p, i);
    int a = 0;
    while (a < D && ++i[a] >= last[a]) {
      i[a] = first[a];
      ++a;
    }
    if (a == D) break;
  }
}

// Keeps the particles whose `drop` flag is 0, in order; returns how many were dropped.
template <int D>
std::size_t drop_particles(InitialParticles<D>& p, const std::vector<char>& drop) {
  std::size_t kept = 0, removed = 0;
  for (std::size_t i = 0; i < p.x.size(); ++i) {
    if (drop[i]) { ++removed; continue; }
    p.x[kept] = p.x[i]; p.v[kept] = p.v[i]; p.normal[kept] = p.normal[i]; p.rho[kept] = p.rho[i];
    p.mass[kept] = p.mass[i]; p.kind[kept] = p.kind[i]; p.body[kept] = p.body[i];
    p.wall_distance[kept] = p.wall_distance[i];
    ++kept;
  }
  p.x.resize(kept); p.v.resize(kept); p.normal.resize(kept); p.rho.resize(kept);
  p.mass.resize(kept); p.kind.resize(kept); p.body.resize(kept); p.wall_distance.resize(kept);
  return removed;
}

// Removes fluid particles closer than `dist` to any boundary particle (overlapping bodies); returns
// how many were removed.
template <int D>
std::size_t remove_fluid_near_walls(InitialParticles<D>& p, double dist) {
  if (!(dist > 0) || p.x.empty()) return 0;
  NeighborGrid<D> grid;
  typename NeighborGrid<D>::Options o;
  o.hashed = true;
  o.cell_size = Real(dist);
  grid.configure(o);
  std::vector<std::uint32_t> perm;
  grid.build(p.x, perm);
  std::vector<char> drop(p.x.size(), 0);
  const Real d2 = Real(dist * dist);
  for (const auto& b : grid.blocks())
    for (std::uint32_t i = b.begin; i < b.end; ++i) {
      const std::uint32_t pi = perm[i];
      if (p.kind[pi] != 0) continue;
      for (std::uint32_t r = b.nbr_begin; r < b.nbr_end && !drop[pi]; ++r)
        for (std::uint32_t j = grid.ranges()[r].begin; j < grid.ranges()[r].end; ++j) {
          const std::uint32_t pj = perm[j];
          if (p.kind[pj] == 1 && (p.x[pi] - p.x[pj]).squaredNorm() < d2) {
            drop[pi] = 1;
            break;
          }
        }
    }
  return drop_particles(p, drop);
}

template <int D>
Vec<D> to_vec(const std::vector<double>& v) {
  Vec<D> r;
  for (int a = 0; a < D; ++a) r[a] = Real(v[a]);
  return r;
}

// Signed distance of p to the surface of a rigid body's shape (negative inside); +inf for meshes (their
// interior is sampled, and the min_boundary_distance rule clears the fluid there).
template <int D>
double rigid_signed_distance(const scene::BodySpec& b, const Vec<D>& p) {
  if (b.shape == "box") {
    double outside = 0, inside = -1e300;
    for (int a = 0; a < D; ++a) {
      const double lo = b.min[std::size_t(a)] - double(p[a]), hi = double(p[a]) - b.max[std::size_t(a)];
      const double d = std::max(lo, hi);
      outside += d > 0 ? d * d : 0;
      inside = std::max(inside, d);
    }
    return outside > 0 ? std::sqrt(outside) : inside;
  }
  const Vec<D> r = p - to_vec<D>(b.center);
  if (b.shape == "sphere" || D == 2) return double(r.norm()) - b.radius;
  if (b.shape == "cylinder") {
    Vec<D> e = to_vec<D>(b.rigid.cylinder_axis);
    e /= e.norm();
    const double along = std::abs(double(r.dot(e))), rr = double((r - r.dot(e) * e).norm());
    const double dr = rr - b.radius, dz = along - 0.5 * b.rigid.cylinder_length;
    if (dr > 0 || dz > 0) return std::sqrt(std::max(dr, 0.0) * std::max(dr, 0.0) + std::max(dz, 0.0) * std::max(dz, 0.0));
    return std::max(dr, dz);
  }
  return std::numeric_limits<double>::infinity();
}

// Removes fluid particles inside solids: a rigid box, sphere or cylinder (rigid_lattice_points gave the
// body the lattice points inside it: together they fill the lattice), and a fixed block or ball of
// boundary particles placed in the water (inside its box; within its radius, where its particles are). The
// block is sampled only `layers` deep and the ball on a lattice of its own, up to half a spacing off the
// fluid's, so the min_boundary_distance rule alone left the fluid inside them (a 0.2 m block at dx 0.005
// held 1296 particles in its hollow; a disc all 317). Fluid between the ball's radius and its interface
// (radius + dx/2) stays unless it is within the clearance of a ball particle: on the same lattice it is a
// spacing away from them, and removing it would open a gap. In 3D a closed mesh obstacle (`layer_side`
// "inside") and a rigid mesh clear the fluid inside their surface the same way (an off-lattice cube kept
// about 670 of its 1,000 interior fluid points under the clearance rule alone).
template <int D>
std::size_t remove_fluid_inside_solids(const scene::Scene& s, InitialParticles<D>& p) {
  std::vector<const scene::BodySpec*> rigid, fixed;
  std::vector<std::size_t> meshes;  // closed mesh obstacles and rigid meshes (3D): a CGAL inside test
  for (std::size_t k = 0; k < s.bodies.size(); ++k) {
    const auto& b = s.bodies[k];
    if (b.kind == "rigid" && b.shape != "mesh") rigid.push_back(&b);
    if (b.kind == "boundary" && (b.shape == "box" || b.shape == "sphere")) fixed.push_back(&b);
    const bool obstacle = b.kind == "rigid" || (b.kind == "boundary" && b.mesh.is_object() &&
                                                b.mesh.value("layer_side", std::string()) == "inside");
    if (D == 3 && b.shape == "mesh" && obstacle) meshes.push_back(k);
  }
  if (rigid.empty() && fixed.empty() && meshes.empty()) return 0;
  std::vector<char> drop(p.x.size(), 0);
  for (std::size_t i = 0; i < p.x.size(); ++i)
    if (p.kind[i] == 0) {
      for (const auto* b : rigid) drop[i] = drop[i] || rigid_signed_distance<D>(*b, p.x[i]) < 0;
      for (const auto* b : fixed) drop[i] = drop[i] || rigid_signed_distance<D>(*b, p.x[i]) < 0;
    }
  if (!meshes.empty()) {
    std::vector<std::size_t> fluid;
    std::vector<Vec<D>> pts;
    for (std::size_t i = 0; i < p.x.size(); ++i)
      if (p.kind[i] == 0 && !drop[i]) {
        fluid.push_back(i);
        pts.push_back(p.x[i]);
      }
    for (const std::size_t k : meshes) {
      const std::vector<char> in = inside_mesh_body<D>(s, k, pts);  // empty: an open mesh, no inside
      for (std::size_t q = 0; q < in.size(); ++q) drop[fluid[q]] = drop[fluid[q]] || in[q];
    }
  }
  return drop_particles(p, drop);
}

// Volume of a rigid shape (area in 2D) [m^d].
template <int D>
double bodies_shape_volume(const scene::BodySpec& b) {
  if (b.shape == "box") {
    double v = 1;
    for (int a = 0; a < D; ++a) v *= b.max[std::size_t(a)] - b.min[std::size_t(a)];
    return v;
  }
  const double pi = 3.14159265358979323846, r2 = b.radius * b.radius;
  if (D == 2) return pi * r2;
  if (b.shape == "sphere") return 4.0 / 3.0 * pi * r2 * b.radius;
  return pi * r2 * b.rigid.cylinder_length;
}

// The nearest point of a rigid shape's surface to a point inside it.
template <int D>
Vec<D> rigid_nearest_surface(const scene::BodySpec& b, const Vec<D>& p) {
  Vec<D> q = p;
  if (b.shape == "box") {
    int axis = 0;
    double best = 1e300, face = 0;
    for (int a = 0; a < D; ++a)
      for (double f : {b.min[std::size_t(a)], b.max[std::size_t(a)]})
        if (std::abs(double(p[a]) - f) < best) {
          best = std::abs(double(p[a]) - f);
          axis = a;
          face = f;
        }
    q[axis] = Real(face);
    return q;
  }
  const Vec<D> c = to_vec<D>(b.center), r = p - c;
  if (b.shape == "sphere" || D == 2) return r.norm() > 0 ? Vec<D>(c + r.normalized() * Real(b.radius)) : p;
  Vec<D> e = to_vec<D>(b.rigid.cylinder_axis);
  e /= e.norm();
  const Real along = r.dot(e);
  const Vec<D> radial = r - along * e;
  const double rr = double(radial.norm()), to_mantle = b.radius - rr,
               to_end = 0.5 * b.rigid.cylinder_length - std::abs(double(along));
  if (to_mantle < to_end) return rr > 0 ? Vec<D>(c + along * e + radial * Real(b.radius / rr)) : p;
  return p + Real((along >= 0 ? 1 : -1) * to_end) * e;
}

// Points of the fluid lattice (cell centres from the first fluid box's corner, else the domain's) inside a
// rigid box, sphere or cylinder, `layers` deep (0: all), with the normal out of the body to the nearest
// surface point and the distance to it (remove_fluid_inside_solids takes the complement).
template <int D>
void rigid_lattice_points(const scene::Scene& s, const scene::BodySpec& b, double dx, std::vector<Vec<D>>& pts,
                          std::vector<Vec<D>>& normals, std::vector<Real>& dists) {
  Vec<D> origin = to_vec<D>(s.domain_min);
  for (const auto& f : s.bodies)
    if (f.kind == "fluid" && f.shape == "box") {
      origin = to_vec<D>(f.min);
      break;
    }
  Vec<D> lo, hi;
  if (b.shape == "box") {
    lo = to_vec<D>(b.min);
    hi = to_vec<D>(b.max);
  } else {
    const double ext = b.shape == "cylinder" && D == 3 ? b.radius + 0.5 * b.rigid.cylinder_length : b.radius;
    lo = to_vec<D>(b.center).array() - Real(ext);
    hi = to_vec<D>(b.center).array() + Real(ext);
  }
  std::array<long, D> first, last;
  for (int a = 0; a < D; ++a) {
    first[a] = long(std::floor(double(lo[a] - origin[a]) / dx - 0.5)) - 1;
    last[a] = long(std::ceil(double(hi[a] - origin[a]) / dx - 0.5)) + 2;
  }
  const double depth = b.layers > 0 ? double(b.layers) * dx : 1e300;
  for_each_lattice_point<D>(first, last, origin, dx, [&](const Vec<D>& p, auto&) {
    const double sd = rigid_signed_distance<D>(b, p);
    if (!(sd < 0) || -sd > depth) return;
    const Vec<D> q = rigid_nearest_surface<D>(b, p);
    const Vec<D> d = q - p;
    const Real len = d.norm();
    pts.push_back(p);
    normals.push_back(len > 0 ? Vec<D>(d / len) : Vec<D>::Zero());
    dists.push_back(len);
  });
}

}  // namespace

template <int D>
std::size_t InitialParticles<D>::count(std::int32_t k) const {
  std::size_t n = 0;
  for (auto q : kind) n += (q == k);
  return n;
}

template <int D>
InitialParticles<D> build_particles(const scene::Scene& s, double B) {
  InitialParticles<D> out;
  const double dx = s.spacing;
  const double cell_volume = std::pow(dx, D);
  const Vec<D> g = to_vec<D>(s.gravity);
  const double gmag = double(g.norm());
  check_particle_budget(s);  // before any allocation: estimates from sizes and dx

  for (std::size_t bi = 0; bi < s.bodies.size(); ++bi) {
    const scene::BodySpec& b = s.bodies[bi];
    const std::string where = s.file.string() + ": bodies." + std::to_string(bi);
    const std::int32_t kind = b.kind == "fluid" ? 0 : 1;  // a rigid body's particles are boundary particles
    const bool rigid = b.kind == "rigid";
    const std::size_t first = out.x.size();
    Pts<D> pts, normals;
    std::vector<Real> dists;  // boundary: distance to the fluid-wall interface along the normal
    // a wall particle's normal points to its nearest point q of the interface, at distance |q - p|
    auto toward = [&](const Vec<D>& p, const Vec<D>& q) {
      const Vec<D> d = q - p;
      const Real len = d.norm();
      normals.push_back(len > 0 ? Vec<D>(d / len) : Vec<D>::Zero());
      dists.push_back(len);
    };

    if (rigid && b.shape != "mesh") {
      // a rigid shape takes the points of the fluid's own lattice inside it (as DualSPHysics draws every
      // body on one grid): fluid and body particles then fill space evenly, with no gap between them wider
      // than a spacing (a body on a lattice of its own, half a spacing off, left a 1.5 dx void around it
      // that cut the fluid's pressure force on it by half: a submerged disc had 37 % of its buoyancy)
      rigid_lattice_points<D>(s, b, dx, pts, normals, dists);
      // the fluid feels the particles' volume, the body's mass comes from the exact shape: say when the
      // lattice misses much of the shape (a face between lattice lines, a body a few spacings across)
      const double vol = bodies_shape_volume<D>(b), got = double(pts.size()) * cell_volume;
      if (b.layers == 0 && vol > 0 && std::abs(got / vol - 1) > 0.05)
        std::fprintf(stderr, "varsph: note: %s: its particles fill %.1f %% of the shape's volume (faces between the "
                     "fluid's lattice lines, or a body a few spacings across): the water sees the particles; place "
                     "faces on lattice lines (multiples of particles.spacing from the fluid's corner) or refine\n",
                     where.c_str(), 100 * got / vol);
    } else if (b.shape == "box" || b.shape == "tank") {
      const Vec<D> lo = to_vec<D>(b.min), hi = to_vec<D>(b.max);
      std::array<long, D> n{};
      for (int a = 0; a < D; ++a) {
        n[a] = cells_in(b.max[a] - b.min[a], dx);
        if (n[a] < 1) throw InputError(where + ": the box is thinner than one particle spacing on axis " + std::to_string(a));
      }
      const long L = b.layers;
      if (b.shape == "box" && kind == 0) {
        for_each_lattice_point<D>({}, n, lo, dx, [&](const Vec<D>& p, auto&) { pts.push_back(p); });
      } else if (b.shape == "box") {
        // solid block: lattice cells within `layers` of its surface; the interface is the block's surface:
        // the normal points out of the block to the nearest face (to the edge or corner where faces tie)
        for_each_lattice_point<D>({}, n, lo, dx, [&](const Vec<D>& p, const std::array<long, D>& i) {
          long depth = L;  // layer index of the nearest face
          for (int a = 0; a < D; ++a) depth = std::min({depth, i[a], n[a] - 1 - i[a]});
          if (depth >= L) return;
          Vec<D> q = p;
          for (int a = 0; a < D; ++a) {
            if (i[a] == depth) q[a] = lo[a];
            else if (n[a] - 1 - i[a] == depth) q[a] = lo[a] + Real(double(n[a]) * dx);
          }
          pts.push_back(p);
          toward(p, q);
        });
      } else {
        // tank: `layers` of lattice cells outside the walls [lo, hi]; open sides are not extended
        std::array<long, D> f{}, l{};
        for (int a = 0; a < D; ++a) {
          f[a] = b.open[2 * a] ? 0 : -L;
          l[a] = b.open[2 * a + 1] ? n[a] : n[a] + L;
        }
        // the interface is the tank's inner surface [lo, hi]: a wall particle's nearest point on it is
        // its position clamped into the box (a corner for particles in a corner region)
        for_each_lattice_point<D>(f, l, lo, dx, [&](const Vec<D>& p, const std::array<long, D>& i) {
          bool outside = false;
          for (int a = 0; a < D; ++a) outside |= i[a] < 0 || i[a] >= n[a];
          if (!outside) return;
          pts.push_back(p);
          Vec<D> q = p;
          for (int a = 0; a < D; ++a) q[a] = std::clamp(p[a], lo[a], lo[a] + Real(double(n[a]) * dx));
          toward(p, q);
        });
        (void)hi;
      }
    } else if (b.shape == "sphere") {
      const Vec<D> c = to_vec<D>(b.center);
      const long n = long(std::ceil(b.radius / dx)) + 1;
      std::array<long, D> f, l;
      f.fill(-n);
      l.fill(n);
      Vec<D> origin = c;
      for (int a = 0; a < D; ++a) origin[a] -= Real(0.5 * dx);  // a lattice point sits at the centre
      for_each_lattice_point<D>(f, l, origin, dx, [&](const Vec<D>& p, auto&) {
        const Vec<D> r = p - c;
        if (double(r.norm()) > b.radius + 1e-9 * dx) return;
        pts.push_back(p);
        // the solid ball's surface sits half a spacing beyond its outermost lattice points
        if (kind == 1) toward(p, r.norm() > 0 ? Vec<D>(c + r.normalized() * Real(b.radius + 0.5 * dx)) : p);
      });
    } else if (b.shape == "points") {
      for (auto& q : b.points) pts.push_back(to_vec<D>(q));
    } else if (b.shape == "mesh") {
      // the geometry module checks its own estimate (area or volume / dx^d) against what is left
      sample_mesh_body<D>(s, bi, max_particles(s) - double(out.x.size()), pts, normals, &dists);
    }
    if (pts.empty()) throw InputError(where + ": the body produced no particles (is it smaller than the spacing?)");
    check_particle_count(s, bi, double(out.x.size() + pts.size()));

    for (std::size_t k = 0; k < pts.size(); ++k) {
      const Vec<D>& p = pts[k];
      for (int a = 0; a < D; ++a)
        if (double(p[a]) < s.domain_min[a] || double(p[a]) > s.domain_max[a])
          throw InputError(where + ": particle at coordinate " + std::to_string(double(p[a])) + " on axis " +
                           std::to_string(a) + " lies outside domain [" + std::to_string(s.domain_min[a]) +
                           ", " + std::to_string(s.domain_max[a]) + "]; enlarge domain.min/max");
      out.x.push_back(p);
      Vec<D> v = to_vec<D>(b.velocity);
      if (!b.velocities.empty()) v = to_vec<D>(b.velocities[k]);
      out.v.push_back(kind == 0 ? v : Vec<D>::Zero());
      out.normal.push_back(k < normals.size() ? normals[k] : Vec<D>::Zero());
      out.wall_distance.push_back(k < dists.size() ? dists[k] : Real(0));
      out.mass.push_back(Real(s.rho0 * cell_volume));
      double rho = s.rho0;
      if (kind == 0 && b.initial_pressure == "hydrostatic" && gmag > 0) {
        // p = rho0 |g| depth below the free surface (along -g); rho from the inverse of eq. (11)
        const double up = -double(g.dot(p)) / gmag;
        Vec<D> surf_pt = Vec<D>::Zero();
        surf_pt[D - 1] = Real(b.free_surface);
        const double up_surface = -double(g.dot(surf_pt)) / gmag;
        const double depth = std::max(0.0, up_surface - up);
        rho = s.rho0 * std::pow(1.0 + s.rho0 * gmag * depth / B, 1.0 / 7.0);
      }
      if (kind == 0 && k < b.pressures.size())  // given initial pressure: rho from the inverse of eq. (11)
        rho = s.rho0 * std::pow(1.0 + b.pressures[k] / B, 1.0 / 7.0);
      out.rho.push_back(Real(rho));
      out.kind.push_back(kind);
      out.body.push_back(int(bi));
    }
    (void)first;
  }
  const std::size_t fluid_drawn = out.count(0);
  if (const std::size_t inside = remove_fluid_inside_solids<D>(s, out)) {
    std::fprintf(stderr, "varsph: note: %s: removed %zu fluid particles inside solid bodies (rigid bodies, boundary "
                 "blocks and balls)\n", s.file.string().c_str(), inside);
  }
  if (const std::size_t removed = remove_fluid_near_walls<D>(out, s.min_boundary_distance)) {
    std::fprintf(stderr, "varsph: note: %s: removed %zu fluid particles closer than %g m to boundary particles "
                 "(overlapping bodies; particles.min_boundary_distance)\n", s.file.string().c_str(), removed,
                 s.min_boundary_distance);
  }
  if (fluid_drawn > 0 && out.count(0) == 0)  // the removals above took all of it (a fluid drawn inside a solid)
    throw InputError(s.file.string() + ": every fluid particle overlaps a boundary body (check the bodies' "
                                       "positions and units)");
  return out;
}

template struct InitialParticles<2>;
template struct InitialParticles<3>;
template InitialParticles<2> build_particles<2>(const scene::Scene&, double);
template InitialParticles<3> build_particles<3>(const scene::Scene&, double);

}  // namespace varsph
