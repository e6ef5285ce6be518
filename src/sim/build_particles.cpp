#include "sim/build_particles.hpp"

#include <cmath>
#include <cstdio>
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
  std::size_t kept = 0, removed = 0;
  for (std::size_t i = 0; i < p.x.size(); ++i) {
    if (drop[i]) { ++removed; continue; }
    p.x[kept] = p.x[i]; p.v[kept] = p.v[i]; p.normal[kept] = p.normal[i]; p.rho[kept] = p.rho[i];
    p.mass[kept] = p.mass[i]; p.kind[kept] = p.kind[i]; p.body[kept] = p.body[i];
    ++kept;
  }
  p.x.resize(kept); p.v.resize(kept); p.normal.resize(kept); p.rho.resize(kept);
  p.mass.resize(kept); p.kind.resize(kept); p.body.resize(kept);
  return removed;
}

template <int D>
Vec<D> to_vec(const std::vector<double>& v) {
  Vec<D> r;
  for (int a = 0; a < D; ++a) r[a] = Real(v[a]);
  return r;
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
    const std::int32_t kind = b.kind == "fluid" ? 0 : 1;
    const std::size_t first = out.x.size();
    Pts<D> pts, normals;

    if (b.shape == "box" || b.shape == "tank") {
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
        // solid block: lattice cells within `layers` of its surface; normals point out of the block
        for_each_lattice_point<D>({}, n, lo, dx, [&](const Vec<D>& p, const std::array<long, D>& i) {
          Vec<D> nrm = Vec<D>::Zero();
          bool near = false;
          for (int a = 0; a < D; ++a) {
            if (i[a] < L) { near = true; if (i[a] == 0) nrm[a] -= 1; }
            if (i[a] >= n[a] - L) { near = true; if (i[a] == n[a] - 1) nrm[a] += 1; }
          }
          if (!near) return;
          pts.push_back(p);
          normals.push_back(nrm.norm() > 0 ? Vec<D>(nrm.normalized()) : nrm);
        });
      } else {
        // tank: `layers` of lattice cells outside the walls [lo, hi]; open sides are not extended
        std::array<long, D> f{}, l{};
        for (int a = 0; a < D; ++a) {
          f[a] = b.open[2 * a] ? 0 : -L;
          l[a] = b.open[2 * a + 1] ? n[a] : n[a] + L;
        }
        for_each_lattice_point<D>(f, l, lo, dx, [&](const Vec<D>& p, const std::array<long, D>& i) {
          Vec<D> nrm = Vec<D>::Zero();
          bool outside = false;
          for (int a = 0; a < D; ++a) {
            if (i[a] < 0) { outside = true; nrm[a] += 1; }
            if (i[a] >= n[a]) { outside = true; nrm[a] -= 1; }
          }
          if (!outside) return;
          pts.push_back(p);
          normals.push_back(Vec<D>(nrm.normalized()));
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
        if (kind == 1) normals.push_back(r.norm() > 0 ? Vec<D>(r.normalized()) : Vec<D>::Zero());
      });
    } else if (b.shape == "points") {
      for (auto& q : b.points) pts.push_back(to_vec<D>(q));
    } else if (b.shape == "mesh") {
      // the geometry module checks its own estimate (area or volume / dx^d) against what is left
      sample_mesh_body<D>(s, bi, max_particles(s) - double(out.x.size()), pts, normals);
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
  if (const std::size_t removed = remove_fluid_near_walls<D>(out, s.min_boundary_distance)) {
    std::fprintf(stderr, "varsph: note: %s: removed %zu fluid particles closer than %g m to boundary particles "
                 "(overlapping bodies; particles.min_boundary_distance)\n", s.file.string().c_str(), removed,
                 s.min_boundary_distance);
    if (out.count(0) == 0)
      throw InputError(s.file.string() + ": every fluid particle overlaps a boundary body (check the bodies' "
                                         "positions and units)");
  }
  return out;
}

template struct InitialParticles<2>;
template struct InitialParticles<3>;
template InitialParticles<2> build_particles<2>(const scene::Scene&, double);
template InitialParticles<3> build_particles<3>(const scene::Scene&, double);

}  // namespace varsph
