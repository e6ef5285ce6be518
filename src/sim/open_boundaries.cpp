#include "sim/open_boundaries.hpp"

#include <algorithm>
#include <chrono>
#include <array>
#include <utility>
#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Dense>

#include "core/errors.hpp"
#include "kernels/kernel_eval.hpp"
#include "physics/corrected_interpolation.hpp"
#include "parallel/domain.hpp"
#include "parallel/halo_rates.hpp"
#include "physics/pair_loop.hpp"

namespace varsph {

namespace {

// The first-order corrected interpolation of physics/corrected_interpolation.hpp (Liu & Liu 2006) for the
// density and the D velocity components at one ghost node at once: one moment matrix, D + 1 right-hand
// sides, one inverse; the same fallbacks (Shepard where nearly dry or ill conditioned, the same limits).
template <int D>
class GhostFit {
 public:
  static constexpr int F = D + 1;  // fields: rho, v_0 .. v_{D-1}
  explicit GhostFit(double support) : inv_s_(1.0 / support) {}
  void add(const Vec<D>& x_gj, double w, double Fg, double V, double rho, const Vec<D>& v) {
    Eigen::Matrix<double, D + 1, 1> u, e;
    u[0] = w;
    e[0] = 1;
    for (int a = 0; a < D; ++a) {
      u[a + 1] = Fg * double(x_gj[a]) / inv_s_;
      e[a + 1] = -double(x_gj[a]) * inv_s_;
    }
    A_.noalias() += (V * u) * e.transpose();
    Eigen::Matrix<double, 1, F> fj;
    fj[0] = rho;
    for (int a = 0; a < D; ++a) fj[1 + a] = double(v[a]);
    B_.noalias() += (V * u) * fj;
    ++count_;
  }
  // False when no fluid neighbour at all (keep the prescribed or previous values).
  bool solve() {
    using CI = physics::CorrectedInterpolation<D>;
    const double ksum = A_(0, 0);
    if (count_ == 0 || !(ksum > 0)) return false;
    sol_.setZero();
    sol_.row(0) = B_.row(0) / ksum;  // Shepard
    if (ksum < CI::kSubmerged) return true;
    const double det = A_.determinant();
    if (!(std::abs(det) >= CI::kDetMin)) return true;
    const Eigen::Matrix<double, D + 1, D + 1> inv = A_.inverse();
    const double cond = A_.cwiseAbs().rowwise().sum().maxCoeff() * inv.cwiseAbs().rowwise().sum().maxCoeff();
    if (!(cond <= CI::kCondMax)) return true;
    sol_ = inv * B_;
    sol_.template bottomRows<D>() *= inv_s_;
    return true;
  }
  using Solution = Eigen::Matrix<double, D + 1, F>;
  const Solution& solution() const { return sol_; }
  // a solution computed elsewhere (the rank that owns the ghost node: several MPI ranks)
  void set_solution(const Solution& s) { sol_ = s; }
  double value(int field) const { return sol_(0, field); }
  Eigen::Matrix<double, D, 1> gradient(int field) const { return sol_.col(field).template tail<D>(); }

 private:
  double inv_s_;
  Eigen::Matrix<double, D + 1, D + 1> A_ = Eigen::Matrix<double, D + 1, D + 1>::Zero();
  Eigen::Matrix<double, D + 1, F> B_ = Eigen::Matrix<double, D + 1, F>::Zero();
  Eigen::Matrix<double, D + 1, F> sol_ = Eigen::Matrix<double, D + 1, F>::Zero();
  int count_ = 0;
};

}  // namespace

template <int D>
OpenBoundaries<D>::OpenBoundaries(const scene::Scene& s, ParticleStore& store) : scene_(s) {
  zone_ = &store.add<std::int32_t>("open_zone", {.exported = true});
  x0_ = &store.add<Vec<D>>("open_x0", {.exported = false, .checkpointed = false});
  v0_ = &store.add<Vec<D>>("open_v0", {.exported = false, .checkpointed = false});
  for (auto& z : zone_->data) z = -1;
  const physics::TaitEos eos(Real(s.rho0), Real(s.c0), Real(s.background_pressure));
  for (const auto& spec : s.open_boundaries) {
    Zone z;
    z.spec = &spec;
    z.inlet = spec.kind == "inlet";
    z.axis = spec.axis;
    z.sign = Real(spec.sign);
    z.face = Real(spec.sign > 0 ? spec.max[std::size_t(spec.axis)] : spec.min[std::size_t(spec.axis)]);
    z.depth = Real(spec.max[std::size_t(spec.axis)] - spec.min[std::size_t(spec.axis)]);
    for (int a = 0; a < D; ++a) {
      z.lo[a] = Real(spec.min[std::size_t(a)]);
      z.hi[a] = Real(spec.max[std::size_t(a)]);
    }
    z.rho_prescribed = spec.pressure_extrapolated || spec.hydrostatic ? Real(s.rho0) : eos.density(Real(spec.pressure));
    z.surface = spec.surface;
    z.gz = Real(-s.gravity[std::size_t(D - 1)]);
    if (spec.oblique) {  // the plane zone's frame (scene/parse_open.cpp normalised the vectors)
      z.oblique = true;
      z.depth = Real(spec.depth);
      for (int a = 0; a < D; ++a) {
        z.n[a] = Real(spec.direction[std::size_t(a)]);
        z.c[a] = Real(spec.center[std::size_t(a)]);
      }
      for (int k = 0; k + 1 < D; ++k) {
        for (int a = 0; a < D; ++a) z.t[std::size_t(k)][a] = Real(spec.tangents[std::size_t(k)][std::size_t(a)]);
        z.hw[std::size_t(k)] = Real(0.5 * spec.width[std::size_t(k)]);
      }
      if (spec.interface != "rectangle") {  // a polygon or a disc: the bounding rectangle's lattice, from its lower corner
        z.shape = spec.interface == "polygon" ? 1 : 2;
        z.poly = spec.polygon;
        z.radius = spec.radius;
        for (int k = 0; k + 1 < D; ++k) {
          z.hw[std::size_t(k)] = Real(-spec.plane_lo[std::size_t(k)]);
          z.ext[std::size_t(k)] = Real(spec.width[std::size_t(k)]);
        }
      }
    }
    zones_.push_back(z);
  }
}

template <int D>
bool OpenBoundaries<D>::in_plane(const Zone& z, const Vec<D>& x, Real tol, bool strict) const {
  const Vec<D> r = x - z.c;
  const double a = double(z.t[0].dot(r)), b = double(z.t[std::size_t(D - 2)].dot(r)), e = double(tol);
  if (z.shape == 2) {  // the disc
    const double q = a * a + b * b, R = z.radius - e;
    return R > 0 && (strict ? q < R * R : q <= R * R);
  }
  // the polygon: the crossing number of a ray from (a, b) along +a (even-odd rule; either orientation)
  const std::size_t n = z.poly.size();
  bool in = false;
  double dmin = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const auto& p = z.poly[i];
    const auto& q = z.poly[j];
    if ((p[1] > b) != (q[1] > b) && a < (q[0] - p[0]) * (b - p[1]) / (q[1] - p[1]) + p[0]) in = !in;
    if (strict && e > 0) {  // the distance to the edge pq
      const double ex = q[0] - p[0], ey = q[1] - p[1];
      const double s = std::clamp(((a - p[0]) * ex + (b - p[1]) * ey) / (ex * ex + ey * ey), 0.0, 1.0);
      dmin = std::min(dmin, std::hypot(a - p[0] - s * ex, b - p[1] - s * ey));
    }
  }
  return in && (!(strict && e > 0) || dmin > e);
}

template <int D>
bool OpenBoundaries<D>::beside(const Zone& z, const Vec<D>& x) const {
  if (z.shape != 0) return in_plane(z, x, Real(0), false);
  if (z.oblique) {
    const Vec<D> r = x - z.c;
    for (int k = 0; k + 1 < D; ++k)
      if (std::abs(z.t[std::size_t(k)].dot(r)) > z.hw[std::size_t(k)]) return false;
    return true;
  }
  for (int a = 0; a < D; ++a)
    if (a != z.axis && (x[a] < z.lo[a] || x[a] > z.hi[a])) return false;
  return true;
}

template <int D>
bool OpenBoundaries<D>::inside(const Zone& z, const Vec<D>& x, Real tol) const {
  if (z.oblique) {
    const Vec<D> r = x - z.c;
    const Real d = z.n.dot(r);
    if (!(d < -tol && d > -z.depth + tol)) return false;
    if (z.shape != 0) return in_plane(z, x, tol, true);
    for (int k = 0; k + 1 < D; ++k)
      if (!(std::abs(z.t[std::size_t(k)].dot(r)) < z.hw[std::size_t(k)] - tol)) return false;
    return true;
  }
  bool in = true;
  for (int a = 0; a < D && in; ++a) in = x[a] > z.lo[a] + tol && x[a] < z.hi[a] - tol;
  return in;
}

template <int D>
std::array<long, D> OpenBoundaries<D>::lattice_cells(const Zone& z, double dx) const {
  std::array<long, D> cells{};
  if (z.oblique) {
    cells[0] = std::lround(double(z.depth) / dx);
    for (int k = 0; k + 1 < D; ++k)
      cells[std::size_t(k + 1)] = z.shape != 0 ? long(std::ceil(double(z.ext[std::size_t(k)]) / dx - 1e-9))
                                               : std::lround(2 * double(z.hw[std::size_t(k)]) / dx);
  } else {
    for (int a = 0; a < D; ++a) cells[std::size_t(a)] = std::lround(double(z.hi[a] - z.lo[a]) / dx);
  }
  return cells;
}

template <int D>
Vec<D> OpenBoundaries<D>::lattice_point(const Zone& z, const std::array<long, D>& idx, double dx) const {
  Vec<D> p;
  if (!z.oblique) {
    for (int a = 0; a < D; ++a) p[a] = Real(double(z.lo[a]) + (double(idx[std::size_t(a)]) + 0.5) * dx);
    return p;
  }
  for (int a = 0; a < D; ++a) {  // c - (i + 1/2) dx n + sum_k ((j_k + 1/2) dx - hw_k) t_k
    double v = double(z.c[a]) - (double(idx[0]) + 0.5) * dx * double(z.n[a]);
    for (int k = 0; k + 1 < D; ++k)
      v += ((double(idx[std::size_t(k + 1)]) + 0.5) * dx - double(z.hw[std::size_t(k)])) * double(z.t[std::size_t(k)][a]);
    p[a] = Real(v);
  }
  return p;
}

template <int D>
Vec<D> OpenBoundaries<D>::inflow(const Zone& z, const Vec<D>& x, double t) const {
  Vec<D> u = Vec<D>::Zero();
  if (!z.inlet) return u;
  const auto& spec = *z.spec;
  double speed = spec.speed_at(t);
  if (z.surface && (spec.profile == "parabolic" || spec.profile == "log_law")) {
    // the water depth H and the height s above the bed (the zone's bottom)
    const double H = spec.level_at(t) - double(z.lo[D - 1]);
    const double sb = std::clamp(double(x[D - 1] - z.lo[D - 1]), 0.0, H);
    if (spec.profile == "parabolic") {  // laminar open-channel (film) profile, zero shear at the surface: u_s (2 s/H - s^2/H^2)
      const double e = sb / H;
      speed *= e * (2 - e);
    } else {  // log law of the wall u = (u* / kappa) ln(s / z0) with u* set by the depth mean U: ln(H / z0) - 1 (e.g. Chanson 2004)
      const double z0 = spec.roughness;
      speed *= sb > z0 ? std::log(sb / z0) / (std::log(H / z0) - 1) : 0.0;
    }
  } else if (spec.profile == "parabolic" && z.shape == 2) {  // a pipe: Hagen-Poiseuille u = peak (1 - r^2 / R^2) about c
    const Vec<D> r = x - z.c;
    const double a = double(z.t[0].dot(r)), b = double(z.t[std::size_t(D - 2)].dot(r));
    speed *= std::max(0.0, 1 - (a * a + b * b) / (z.radius * z.radius));
  } else if (spec.profile == "parabolic" && z.oblique) {  // the same across an oblique zone's width (2D), s along its tangent
    const double W = 2 * double(z.hw[0]);
    const double sc = std::clamp(double(z.t[0].dot(x - z.c)) + 0.5 * W, 0.0, W);
    speed *= 4.0 * sc * (W - sc) / (W * W);
  } else if (spec.profile == "parabolic") {  // 2D plane Poiseuille profile across the zone: 4 u_peak s (W - s) / W^2
    const int across = 1 - z.axis;
    const double W = double(z.hi[across] - z.lo[across]);
    const double sc = std::clamp(double(x[across] - z.lo[across]), 0.0, W);
    speed *= 4.0 * sc * (W - sc) / (W * W);
  }
  if (z.oblique) return Vec<D>(z.n * Real(speed));
  u[z.axis] = Real(double(z.sign) * speed);
  return u;
}

template <int D>
void OpenBoundaries<D>::setup(Simulation<D>& sim, Real support) {
  const auto& s = scene_;
  auto& f = sim.fields();
  auto& store = sim.store();
  const std::string file = s.file.string();
  const auto key = [&](std::size_t k, const char* leaf) {
    return file + ": key 'open_boundaries." + std::to_string(k) + "." + leaf + "' (zone '" + s.open_boundaries[k].name + "'): ";
  };
  // the variational scheme holds the buffer particles through its fixed point (their chord is prescribed:
  // integrators/variational.cpp, hold_buffers); the multi-stage schemes' stages are not checked yet
  if (s.integrator != "verlet" && s.integrator != "verlet_dsph" && s.integrator != "symplectic_euler" &&
      s.integrator != "variational")
    throw InputError(file + ": key 'integrator.type': \"" + s.integrator + "\" does not run with open boundaries yet "
                     "(the buffer update is not checked with its stages; expected "
                     "\"verlet\", \"verlet_dsph\", \"symplectic_euler\" or \"variational\"; docs/open_boundaries.md)");
  const double dx = s.spacing;
  const std::size_t n = store.size();
  for (std::size_t k = 0; k < zones_.size(); ++k) {
    const Zone& z = zones_[k];
    if (double(z.depth) < double(support) * (1 - 1e-9)) {
      std::ostringstream m;
      m << key(k, z.oblique ? "depth" : z.sign > 0 ? "min" : "max") << "the zone is " << double(z.depth) << " m deep along its direction, "
        << "thinner than the kernel support " << double(support) << " m: buffer particles must fill the support "
        << "of the fluid next to the interface; make it at least " << long(std::ceil(double(support) / dx - 1e-9))
        << " spacings deep";
      throw InputError(m.str());
    }
    // the interface must face the fluid: fluid particles within a spacing beyond it. An outlet that no fluid
    // reaches yet (the sheets of a jet on a plate arrive later) is accepted unless fluid lies beyond its outer
    // face instead, the signature of a reversed direction
    bool faces_fluid = false, faces_back = false;
    for (std::size_t i = 0; i < n && !faces_fluid; ++i) {
      if (f.kind[i] != 0 || !beside(z, f.x[i])) continue;
      const Real d = distance(z, f.x[i]);
      faces_fluid = d > 0 && d < Real(dx);
      faces_back = faces_back || (d < -z.depth && d > -z.depth - Real(dx));
    }
    if (!faces_fluid && (z.inlet || faces_back)) {
      std::ostringstream where;
      if (z.oblique) {
        where << "through (";
        for (int a = 0; a < D; ++a) where << (a ? ", " : "") << double(z.c[a]);
        where << ")";
      } else {
        where << "at " << std::to_string(double(z.face)) << " on axis " << z.axis;
      }
      throw InputError(key(k, "direction") + "no fluid lies within a spacing beyond the zone's face " + where.str() +
                       ": the direction must point from the zone into the fluid");
    }
    // a wall inside the zone: a boundary particle more than a hundredth of a spacing inside the box
    const Real tol = Real(0.01 * dx);
    for (std::size_t i = 0; i < n; ++i) {
      if (f.kind[i] == 0) continue;
      if (inside(z, f.x[i], tol)) {
        std::ostringstream m;
        m << key(k, z.shape == 1 ? "polygon" : z.shape == 2 ? "radius" : z.oblique ? "center" : "min") << "the zone overlaps a wall: boundary particle id " << f.id[i] << " at (";
        for (int a = 0; a < D; ++a) m << (a ? ", " : "") << double(f.x[i][a]);
        m << ") of bodies." << f.body[i] << " lies inside it; place the zone in the fluid, between the walls";
        throw InputError(m.str());
      }
    }
  }
  check_outlets_reachable(sim);
  // the fluid inside the zones gives way to the zones' lattices (lattice points at (i + 1/2) dx from the
  // box's lower corner: the fluid's own lattice when the box faces lie on its lattice lines)
  std::uint32_t fluid_src = UINT32_MAX;
  for (std::size_t i = 0; i < n && fluid_src == UINT32_MAX; ++i)
    if (f.kind[i] == 0) fluid_src = std::uint32_t(i);
  created_src_.clear();
  created_zone_.clear();
  std::vector<Vec<D>> pts;
  std::vector<char> fed;
  for (std::size_t k = 0; k < zones_.size(); ++k) {
    const Zone& z = zones_[k];
    const std::array<long, D> cells = lattice_cells(z, dx);  // oblique: along -n, then the tangents
    long total = 1;
    for (int a = 0; a < D; ++a) total *= cells[std::size_t(a)];
    // an outlet's lattice only where fluid lies beside its interface (its first spacing beyond the face, the
    // same cell across the direction): a box taller than a free-surface flow holds no buffer above the water
    const auto across_cell = [&](const Vec<D>& x) {
      long key = 0, mul = 1;
      if (z.oblique) {  // the column along the tangents
        for (int j = 0; j + 1 < D; ++j) {
          const long cj = cells[std::size_t(j + 1)];
          const double sj = double(z.t[std::size_t(j)].dot(x - z.c) + z.hw[std::size_t(j)]);
          key += std::clamp(long(std::floor(sj / dx)), 0L, cj - 1) * mul;
          mul *= cj;
        }
        return key;
      }
      for (int a = 0; a < D; ++a) {
        if (a == z.axis) continue;
        const long c = std::clamp(long(std::floor(double(x[a] - z.lo[a]) / dx)), 0L, cells[std::size_t(a)] - 1);
        key += c * mul;
        mul *= cells[std::size_t(a)];
      }
      return key;
    };
    if (!z.inlet) {
      fed.assign(std::size_t(total / cells[std::size_t(z.oblique ? 0 : z.axis)]), 0);
      for (std::size_t i = 0; i < n; ++i) {
        if (f.kind[i] != 0 || !beside(z, f.x[i])) continue;
        const Real d = distance(z, f.x[i]);
        if (d > 0 && d < Real(dx)) fed[std::size_t(across_cell(f.x[i]))] = 1;
      }
    }
    for (long c = 0; c < total; ++c) {
      long r = c;
      std::array<long, D> idx{};
      for (int a = 0; a < D; ++a) {
        idx[std::size_t(a)] = r % cells[std::size_t(a)];
        r /= cells[std::size_t(a)];
      }
      const Vec<D> p = lattice_point(z, idx, dx);
      if (z.shape != 0 && !in_plane(z, p, Real(0), true)) continue;  // a polygon or disc: its nodes inside only
      if (!wet(z, p, sim.time())) continue;  // a free-surface inlet: only below its water level
      if (!z.inlet && !fed[std::size_t(across_cell(p))]) continue;
      pts.push_back(p);
      created_src_.push_back(fluid_src);
      created_zone_.push_back(std::int32_t(k));
    }
  }
  const std::size_t first = sim.create_particles(created_src_);
  const Real mass = Real(s.rho0 * std::pow(dx, D));
  for (std::size_t c = 0; c < pts.size(); ++c) {
    const std::size_t i = first + c;
    const Zone& z = zones_[std::size_t(created_zone_[c])];
    f.x[i] = pts[c];
    f.v[i] = inflow(z, pts[c], 0.0);
    f.a[i] = Vec<D>::Zero();
    f.rho[i] = z.rho_prescribed;
    f.drho[i] = 0;
    f.mass[i] = mass;
    f.kind[i] = 0;
    f.normal[i] = Vec<D>::Zero();
    f.body[i] = -1;
    zone_->data[i] = created_zone_[c];
  }
  kept_.clear();
  for (std::size_t i = 0; i < store.size(); ++i) {
    bool drop = false;
    if (i < n && f.kind[i] == 0)
      for (const Zone& z : zones_) drop = drop || inside(z, f.x[i], Real(0));
    if (!drop) kept_.push_back(std::uint32_t(i));
  }
  store.compact(kept_);
  sim.recount_kinds();
}

template <int D>
void OpenBoundaries<D>::check_outlets_reachable(Simulation<D>& sim) const {
  // Every outlet must be reachable from an inlet through the domain, as the fluid would flow: a flood fill
  // over cells of one spacing (lattice-aligned: the first inlet's corner is a cell corner, so lattice
  // particles sit at cell centres), 2D 4-connected / 3D 6-connected, from the cells just beyond each inlet's
  // interface, through every cell that holds no boundary particle and lies in no zone (fluid entering an
  // inlet zone or crossing a zone's outer face leaves the domain), until it meets an outlet's cells. Walls of
  // particles at most a spacing apart leave no face-connected gap. Without inlets (a tank draining through an
  // outlet) there is nothing to check.
  const auto& s = scene_;
  std::size_t first_inlet = zones_.size();
  for (std::size_t k = 0; k < zones_.size() && first_inlet == zones_.size(); ++k)
    if (zones_[k].inlet) first_inlet = k;
  if (first_inlet == zones_.size() || zones_.size() > 250) return;
  const auto& f = sim.fields();
  const std::size_t n = sim.size();
  const double dx = s.spacing;
  // the box: the domain (a hash-grid domain is unbounded: the particles' and zones' box, one cell around)
  std::array<double, D> lo{}, hi{};
  for (int a = 0; a < D; ++a) {
    lo[std::size_t(a)] = s.domain_min[std::size_t(a)];
    hi[std::size_t(a)] = s.domain_max[std::size_t(a)];
  }
  if (s.neighbor_search == "hash") {
    std::array<double, D> blo, bhi;
    blo.fill(std::numeric_limits<double>::infinity());
    bhi.fill(-std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < n; ++i)
      for (int a = 0; a < D; ++a) {
        blo[std::size_t(a)] = std::min(blo[std::size_t(a)], double(f.x[i][a]));
        bhi[std::size_t(a)] = std::max(bhi[std::size_t(a)], double(f.x[i][a]));
      }
    for (const Zone& z : zones_)
      for (int a = 0; a < D; ++a) {
        blo[std::size_t(a)] = std::min(blo[std::size_t(a)], double(z.lo[a]));
        bhi[std::size_t(a)] = std::max(bhi[std::size_t(a)], double(z.hi[a]));
      }
    for (int a = 0; a < D; ++a)
      if (!s.periodic[std::size_t(a)]) {
        lo[std::size_t(a)] = std::max(lo[std::size_t(a)], blo[std::size_t(a)] - dx);
        hi[std::size_t(a)] = std::min(hi[std::size_t(a)], bhi[std::size_t(a)] + dx);
      }
  }
  // cell c on axis a covers [org + c dx, org + (c+1) dx); org on the first inlet's lattice lines
  std::array<double, D> org{};
  std::array<std::int64_t, D> cells{};
  std::int64_t total = 1;
  for (int a = 0; a < D; ++a) {
    const double c = double(zones_[first_inlet].lo[a]);
    org[std::size_t(a)] = c - std::ceil((c - lo[std::size_t(a)]) / dx - 1e-9) * dx;
    cells[std::size_t(a)] =
        std::max<std::int64_t>(1, std::int64_t(std::ceil((hi[std::size_t(a)] - org[std::size_t(a)]) / dx - 1e-9)));
    total *= cells[std::size_t(a)];
  }
  if (total > (std::int64_t(1) << 28)) return;  // over 2.7e8 cells (256 MB): not checked (docs/open_boundaries.md)
  // state: open, wall, reached, or 3 + k inside zone k
  enum : std::uint8_t { kOpen = 0, kWall = 1, kReached = 2, kZone = 3 };
  std::vector<std::uint8_t> state(std::size_t(total), kOpen);
  for (std::size_t i = 0; i < n; ++i) {
    if (f.kind[i] == 0) continue;
    std::int64_t key = 0, mul = 1;
    bool in = true;
    for (int a = 0; a < D && in; ++a) {
      const std::int64_t c = std::int64_t(std::floor((double(f.x[i][a]) - org[std::size_t(a)]) / dx));
      in = c >= 0 && c < cells[std::size_t(a)];
      key += c * mul;
      mul *= cells[std::size_t(a)];
    }
    if (in) state[std::size_t(key)] = kWall;
  }
  // the cells whose centres lie in a zone's box
  const auto cell_centre = [&](const std::array<std::int64_t, D>& c) {
    Vec<D> p;
    for (int a = 0; a < D; ++a) p[a] = Real(org[std::size_t(a)] + (double(c[std::size_t(a)]) + 0.5) * dx);
    return p;
  };
  // an oblique zone: the cells of its bounding box (two cells around) whose centre passes `take`
  const auto for_box_cells = [&](const Zone& z, auto&& take, auto&& visit) {
    std::array<std::int64_t, D> c0{}, c1{};
    for (int a = 0; a < D; ++a) {
      const double o = org[std::size_t(a)];
      c0[std::size_t(a)] = std::max<std::int64_t>(0, std::int64_t(std::floor((double(z.lo[a]) - o) / dx)) - 2);
      c1[std::size_t(a)] = std::min<std::int64_t>(cells[std::size_t(a)], std::int64_t(std::floor((double(z.hi[a]) - o) / dx)) + 3);
      if (c1[std::size_t(a)] <= c0[std::size_t(a)]) return;
    }
    std::array<std::int64_t, D> c = c0;
    for (;;) {
      if (take(cell_centre(c))) {
        std::int64_t key = 0, mul = 1;
        for (int a = 0; a < D; ++a) {
          key += c[std::size_t(a)] * mul;
          mul *= cells[std::size_t(a)];
        }
        visit(key, c);
      }
      int a = 0;
      for (; a < D; ++a) {
        if (++c[std::size_t(a)] < c1[std::size_t(a)]) break;
        c[std::size_t(a)] = c0[std::size_t(a)];
      }
      if (a == D) return;
    }
  };
  const auto for_zone_cells = [&](const Zone& z, auto&& visit) {
    if (z.oblique) return for_box_cells(z, [&](const Vec<D>& p) { return inside(z, p, Real(0)); }, visit);
    std::array<std::int64_t, D> c0{}, c1{};
    for (int a = 0; a < D; ++a) {
      const double o = org[std::size_t(a)];
      c0[std::size_t(a)] = std::max<std::int64_t>(0, std::int64_t(std::ceil((double(z.lo[a]) - o) / dx - 0.5 - 1e-9)));
      c1[std::size_t(a)] = std::min<std::int64_t>(cells[std::size_t(a)],
                                                  std::int64_t(std::floor((double(z.hi[a]) - o) / dx - 0.5 + 1e-9)) + 1);
      if (c1[std::size_t(a)] <= c0[std::size_t(a)]) return;
    }
    std::array<std::int64_t, D> c = c0;
    for (;;) {
      std::int64_t key = 0, mul = 1;
      for (int a = 0; a < D; ++a) {
        key += c[std::size_t(a)] * mul;
        mul *= cells[std::size_t(a)];
      }
      visit(key, c);
      int a = 0;
      for (; a < D; ++a) {
        if (++c[std::size_t(a)] < c1[std::size_t(a)]) break;
        c[std::size_t(a)] = c0[std::size_t(a)];
      }
      if (a == D) return;
    }
  };
  for (std::size_t k = 0; k < zones_.size(); ++k)
    for_zone_cells(zones_[k], [&](std::int64_t key, const auto&) { state[std::size_t(key)] = std::uint8_t(kZone + k); });
  std::vector<char> outlet_reached(zones_.size(), 0);
  std::vector<std::int64_t> front;
  const auto visit = [&](std::int64_t key) {
    std::uint8_t& st = state[std::size_t(key)];
    if (st == kOpen) {
      st = kReached;
      front.push_back(key);
    } else if (st >= kZone && !zones_[std::size_t(st - kZone)].inlet) {
      outlet_reached[std::size_t(st - kZone)] = 1;
    }
  };
  // the neighbour of cell c on axis a at offset step, periodic axes wrapped; false beyond the box
  const auto neighbour = [&](std::int64_t key, std::int64_t ca, int a, int step, std::int64_t& nb) {
    std::int64_t mul = 1;
    for (int b = 0; b < a; ++b) mul *= cells[std::size_t(b)];
    const std::int64_t na = cells[std::size_t(a)];
    std::int64_t cb = ca + step;
    if (cb < 0 || cb >= na) {
      if (!s.periodic[std::size_t(a)]) return false;
      cb = (cb + na) % na;
    }
    nb = key + (cb - ca) * mul;
    return true;
  };
  // seeds: the cells beyond each inlet's interface (its direction's neighbours of the zone's cells)
  for (std::size_t k = 0; k < zones_.size(); ++k) {
    const Zone& z = zones_[k];
    if (!z.inlet) continue;
    if (z.oblique) {  // the cells whose centres lie within 1.5 spacings beyond the interface, beside it
      for_box_cells(
          z, [&](const Vec<D>& p) { const Real d = distance(z, p); return d > 0 && d <= Real(1.5 * dx) && beside(z, p); },
          [&](std::int64_t key, const auto&) { visit(key); });
      continue;
    }
    for_zone_cells(z, [&](std::int64_t key, const auto& c) {
      std::int64_t nb;
      if (neighbour(key, c[std::size_t(z.axis)], z.axis, z.sign > 0 ? 1 : -1, nb)) visit(nb);
    });
  }
  while (!front.empty()) {  // depth-first (a stack): the set reached does not depend on the order
    const std::int64_t key = front.back();
    front.pop_back();
    std::int64_t rest = key;
    for (int a = 0; a < D; ++a) {
      const std::int64_t ca = rest % cells[std::size_t(a)];
      rest /= cells[std::size_t(a)];
      for (const int step : {-1, 1}) {
        std::int64_t nb;
        if (neighbour(key, ca, a, step, nb)) visit(nb);
      }
    }
  }
  for (std::size_t k = 0; k < zones_.size(); ++k) {
    if (zones_[k].inlet || outlet_reached[k]) continue;
    std::ostringstream m;
    m << s.file.string() << ": key 'open_boundaries." << k << ".min' (zone '" << s.open_boundaries[k].name << "'): "
      << "no path through the domain leads from an inlet to this outlet (walls close it off from inlet '"
      << s.open_boundaries[first_inlet].name << "'" << (zones_.size() > 2 ? " and every other inlet" : "")
      << "); expected an outlet the inflow can reach: move the zone or open the walls between them";
    throw InputError(m.str());
  }
}

namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

template <int D>
void OpenBoundaries<D>::before_step(Simulation<D>& sim) {
  const auto t0 = std::chrono::steady_clock::now();
  auto& f = sim.fields();
  const std::int32_t* zone = zone_->data.data();
  const Vec<D>* x = f.x.data.data();
  const Vec<D>* v = f.v.data.data();
  Vec<D>* x0 = x0_->data.data();
  Vec<D>* v0 = v0_->data.data();
  for_each_particle(sim.size(), [&](std::size_t i) {
    if (zone[i] < 0) return;
    x0[i] = x[i];
    v0[i] = v[i];
  });
  step_t0_ = sim.time();
  stepping_ = true;
  placed_ = false;
  impose_seconds_ += seconds_since(t0);
}

template <int D>
void OpenBoundaries<D>::place_buffers(Simulation<D>& sim) {
  if (!stepping_) return;
  // buffer particles move with their velocity of the step's start (Tafuni 2018 sec. 3.1), not the fluid's
  // forces; each particle its own slots (a worksharing loop inside a step's team)
  auto& f = sim.fields();
  const Real dt = Real(sim.dt());
  const std::int32_t* zone = zone_->data.data();
  Vec<D>* x = f.x.data.data();
  const Vec<D>* x0 = x0_->data.data();
  const Vec<D>* v0 = v0_->data.data();
  for_each_particle(sim.size(), [&](std::size_t i) {
    if (zone[i] >= 0) x[i] = x0[i] + dt * v0[i];
  });
  team_single([&] { placed_ = true; });
}

namespace {

// One transition of one particle, keyed by its place in the serial storage order (its index in one process,
// its order tag on several ranks), so that the flows are summed and the created particles numbered in the
// order one process would use, whatever the rank count.
struct Transition {
  std::uint64_t key;
  double mass_in, mass_out;
  std::int32_t removed_outlet, removed, created, pad;
};

// Every rank's transitions, sorted by key (unique: a tag belongs to one owned particle). One process: its own.
std::vector<Transition> all_transitions(parallel::Communicator& comm, const std::vector<Transition>& mine) {
  std::vector<Transition> all;
  if (comm.size() == 1) {
    all = mine;
  } else {
    const auto counts = comm.allgather(std::int64_t(mine.size()));
    const int me = comm.rank(), P = comm.size();
    std::vector<std::vector<Transition>> in(static_cast<std::size_t>(P));
    std::vector<parallel::Message> out_m, in_m;
    for (int q = 0; q < P; ++q) {
      if (q == me) continue;
      if (!mine.empty())
        out_m.push_back({q, reinterpret_cast<std::byte*>(const_cast<Transition*>(mine.data())), mine.size() * sizeof(Transition)});
      in[std::size_t(q)].resize(std::size_t(counts[std::size_t(q)]));
      if (!in[std::size_t(q)].empty())
        in_m.push_back({q, reinterpret_cast<std::byte*>(in[std::size_t(q)].data()), in[std::size_t(q)].size() * sizeof(Transition)});
    }
    comm.exchange(out_m, in_m);
    for (int q = 0; q < P; ++q) {
      const auto& v = q == me ? mine : in[std::size_t(q)];
      all.insert(all.end(), v.begin(), v.end());
    }
  }
  std::sort(all.begin(), all.end(), [](const Transition& a, const Transition& b) { return a.key < b.key; });
  return all;
}

}  // namespace

template <int D>
void OpenBoundaries<D>::after_step(Simulation<D>& sim) {
  auto& f = sim.fields();
  auto& flow = sim.flow();
  parallel::Domain<D>* dom = sim.domain();
  auto t0 = std::chrono::steady_clock::now();
  // the buffer particles were placed before the drift's sort (place_buffers); an integrator that did not
  // sort leaves them to be placed here, and the grid to be rebuilt below
  const bool unplaced = !placed_;
  if (unplaced) place_buffers(sim);
  stepping_ = false;
  // transitions of the owned particles in storage order; the flows and the creation order below follow the
  // serial storage order across ranks (the same decisions and sums on any thread and rank count)
  created_src_.clear();
  created_zone_.clear();
  removed_.clear();
  std::vector<Transition> mine;
  std::vector<std::uint64_t> created_keys;
  const std::size_t n = sim.size();
  std::int32_t* zone = zone_->data.data();
  for (std::size_t i = 0; i < n; ++i) {
    if (f.kind[i] != 0) continue;
    Transition e{dom ? std::uint64_t(dom->order_tag(i)) : std::uint64_t(i), 0.0, 0.0, 0, 0, 0, 0};
    bool any = false;
    const std::int32_t zi = zone[i];
    if (zi >= 0) {
      const Zone& z = zones_[std::size_t(zi)];
      const Real d = distance(z, f.x[i]);
      if (d >= 0) {  // crossed the interface into the fluid
        zone[i] = -1;
        e.mass_in = double(f.mass[i]);
        any = true;
        if (z.inlet && wet(z, f.x[i], sim.time())) {  // no copy above a free-surface inlet's (fallen) level
          created_src_.push_back(std::uint32_t(i));
          created_zone_.push_back(zi);
          created_keys.push_back(e.key);
          e.created = 1;
        }
      } else if (d < -z.depth) {  // left the zone through its outer face
        removed_.push_back(std::uint32_t(i));
        e.removed = 1;
        e.removed_outlet = z.inlet ? 0 : 1;
        any = true;
      } else if (z.surface && !wet(z, f.x[i], sim.time())) {  // above a fallen water level: the buffer shrinks
        removed_.push_back(std::uint32_t(i));
        e.removed = 1;
        any = true;
      }
      if (any) mine.push_back(e);
      continue;
    }
    for (std::size_t k = 0; k < zones_.size(); ++k) {
      const Zone& z = zones_[k];
      if (!beside(z, f.x[i])) continue;
      const Real d = distance(z, f.x[i]);
      if (d >= 0) continue;
      any = true;
      if (z.inlet) {  // backflow into an inlet (near its walls, where the inflow vanishes): leaves the domain
        removed_.push_back(std::uint32_t(i));
        e.mass_out = double(f.mass[i]);
        e.removed = e.removed_outlet = 1;
        break;
      }
      zone[i] = std::int32_t(k);  // fluid entering an outlet zone becomes a buffer particle
      e.mass_out = double(f.mass[i]);
      if (d < -z.depth) {  // jumped the whole zone in one step
        removed_.push_back(std::uint32_t(i));
        e.removed = e.removed_outlet = 1;
      }
      break;
    }
    if (any) mine.push_back(e);
  }
  // the flows in serial order; each created particle's place in the serial creation order
  const std::vector<Transition> all = all_transitions(sim.comm(), mine);
  std::int64_t created_total = 0, removed_total = 0;
  order_.clear();
  std::size_t p = 0;
  for (const Transition& e : all) {
    flow.mass_in += e.mass_in;
    flow.mass_out_outlet += e.mass_out;
    flow.removed_outlet += e.removed_outlet;
    removed_total += e.removed;
    if (e.created) {
      if (p < created_keys.size() && created_keys[p] == e.key) {
        order_.push_back(created_total);
        ++p;
      }
      ++created_total;
    }
  }
  if (p != created_keys.size()) throw std::logic_error("OpenBoundaries: a created particle lost in the ordering");
  bool changed = unplaced || created_total > 0 || removed_total > 0;
  if (created_total > 0) {  // a copy one zone depth upstream takes each crossing particle's place
    const std::size_t first = sim.create_particles(created_src_, order_, created_total);
    const double t = sim.time();
    for (std::size_t c = 0; c < created_src_.size(); ++c) {
      const std::size_t i = first + c;
      const Zone& z = zones_[std::size_t(created_zone_[c])];
      Vec<D> shift = Vec<D>::Zero();
      if (z.oblique) shift = -z.depth * z.n;  // one depth upstream along the normal
      else shift[z.axis] = -z.sign * z.depth;
      f.x[i] += shift;
      for (auto* pl : sim.position_like()) pl->data[i] += shift;
      zone_->data[i] = created_zone_[c];
      f.v[i] = inflow(z, f.x[i], t);
      f.body[i] = -1;
    }
    flow.created += long(created_total);
  }
  std::size_t risen = 0;  // a varying water level that rose: new lattice rows (the same count on every rank)
  for (const Zone& z : zones_)
    if (z.spec->level_varies()) {
      risen = fill_risen_rows(sim, step_t0_, sim.time(), created_total);
      break;
    }
  if (!removed_.empty()) {  // removed_ is ascending (storage order) and below the created copies
    kept_.clear();
    std::size_t r = 0;
    const std::size_t total = dom ? sim.size() : sim.store().size();  // owned (ghosts are rebuilt by the rebin)
    for (std::uint32_t i = 0; i < std::uint32_t(total); ++i) {
      if (r < removed_.size() && removed_[r] == i) {
        ++r;
        continue;
      }
      kept_.push_back(i);
    }
    if (dom) dom->compact_owned(sim.store(), kept_);
    else sim.store().compact(kept_);
  }
  changed = changed || risen > 0;
  if (changed) {  // every rank alike (the totals are global)
    sim.recount_kinds();
    sim.rebin();  // the sort and the grid for the new set of particles
  }
  transition_seconds_ += seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  impose(sim);
  impose_seconds_ += seconds_since(t0);
}

template <int D>
std::size_t OpenBoundaries<D>::fill_risen_rows(Simulation<D>& sim, double t0, double t1, std::int64_t created_before) {
  auto& f = sim.fields();
  const double dx = scene_.spacing;
  row_pts_.clear();
  created_src_.clear();
  created_zone_.clear();
  for (std::size_t k = 0; k < zones_.size(); ++k) {
    const Zone& z = zones_[k];
    if (!z.spec->level_varies()) continue;
    const double l0 = z.spec->level_at(t0), l1 = z.spec->level_at(t1);
    if (!(l1 > l0)) continue;
    // the zone's lattice points (as in setup) whose row was dry at t0 and is wet at t1
    std::array<long, D> cells{};
    long total = 1;
    for (int a = 0; a < D; ++a) {
      cells[std::size_t(a)] = std::lround(double(z.hi[a] - z.lo[a]) / dx);
      total *= cells[std::size_t(a)];
    }
    for (long c = 0; c < total; ++c) {
      long r = c;
      Vec<D> p;
      for (int a = 0; a < D; ++a) {
        const long ia = r % cells[std::size_t(a)];
        r /= cells[std::size_t(a)];
        p[a] = Real(double(z.lo[a]) + (double(ia) + 0.5) * dx);
      }
      if (wet(z, p, t0) || !wet(z, p, t1)) continue;
      row_pts_.push_back(p);
      created_zone_.push_back(std::int32_t(k));
    }
  }
  if (row_pts_.empty()) return 0;
  // copies of a fluid particle (every registered field gets a value), then the lattice point's state
  std::uint32_t src = UINT32_MAX;
  std::size_t first = 0, made = row_pts_.size();
  if (parallel::Domain<D>* dom = sim.domain()) {
    // one process's source, the first fluid particle in its storage order: the smallest order tag on any rank
    std::int64_t best = std::numeric_limits<std::int64_t>::max();
    for (std::size_t i = 0; i < sim.size(); ++i)
      if (f.kind[i] == 0 && dom->order_tag(i) < best) {
        best = dom->order_tag(i);
        src = std::uint32_t(i);
      }
    const std::vector<std::int64_t> all = sim.comm().allgather(best);
    int winner = -1;  // tags are unique: one rank holds the smallest
    std::int64_t lowest = std::numeric_limits<std::int64_t>::max();
    for (int q = 0; q < int(all.size()); ++q)
      if (all[std::size_t(q)] < lowest) lowest = all[std::size_t(q)], winner = q;
    if (winner < 0) return 0;  // no fluid left on any rank: nothing to copy from (every rank alike)
    made = winner == sim.comm().rank() ? row_pts_.size() : 0;
    created_src_.assign(made, src);
    order_.resize(made);
    for (std::size_t c = 0; c < made; ++c) order_[c] = std::int64_t(c);
    first = sim.create_particles(created_src_, order_, std::int64_t(row_pts_.size()), created_before);
  } else {
    for (std::size_t i = 0; i < sim.size() && src == UINT32_MAX; ++i)
      if (f.kind[i] == 0) src = std::uint32_t(i);
    if (src == UINT32_MAX) return 0;  // no fluid left at all: nothing to copy from
    created_src_.assign(row_pts_.size(), src);
    first = sim.create_particles(created_src_);
  }
  const Real mass = Real(scene_.rho0 * std::pow(dx, D));
  for (std::size_t c = 0; c < made; ++c) {
    const std::size_t i = first + c;
    const Zone& z = zones_[std::size_t(created_zone_[c])];
    f.x[i] = row_pts_[c];
    for (auto* pl : sim.position_like()) pl->data[i] = row_pts_[c];
    f.v[i] = inflow(z, row_pts_[c], t1);
    f.a[i] = Vec<D>::Zero();
    f.rho[i] = z.rho_prescribed;
    f.drho[i] = 0;
    f.mass[i] = mass;
    f.normal[i] = Vec<D>::Zero();
    f.body[i] = -1;
    zone_->data[i] = created_zone_[c];
  }
  sim.flow().created += long(row_pts_.size());
  return row_pts_.size();
}

namespace {

// A ghost node's first-order fit asked of the rank that owns its cell (several MPI ranks), and the answer.
template <int D>
struct FitRequest {
  Vec<D> xg;
};
template <int D>
struct FitAnswer {
  typename GhostFit<D>::Solution sol;
  std::int32_t ok, pad;
};

}  // namespace

template <int D>
double OpenBoundaries<D>::normal_gradient(const Zone& z, const Vec<D>& x, double t) const {
  // The normal momentum balance of a buffer particle that moves with the prescribed u(x, t) n, u independent
  // of the coordinate along n (so (u . grad) u = 0):  dp/dn = rho0 (g - du/dt) . n + mu lap u  (the pressure condition
  // compatible with a prescribed velocity, Gresho & Sani 1987, Int. J. Numer. Meth. Fluids 7:1111-1145). Both
  // derivatives by differences of the profile (exact for the 2D and pipe parabolas, whose lap u is constant):
  // time +-1e-4 s (one-sided at t = 0), across the interface +-dx/10 along each tangent (buffer nodes lie half
  // a spacing or more inside the zone, where every profile is smooth).
  const Vec<D> n = normal(z);
  const double dt = 1e-4, t0 = std::max(0.0, t - dt);
  const double dudt = double(n.dot(inflow(z, x, t + dt) - inflow(z, x, t0))) / (t + dt - t0);
  double lap = 0;
  if (scene_.laminar_viscosity) {
    const double h = 0.1 * scene_.spacing;
    const double u0 = double(n.dot(inflow(z, x, t)));
    for (int k = 0; k + 1 < D; ++k) {  // the tangents: an oblique zone's, else the axes across the direction
      Vec<D> e = Vec<D>::Zero();
      if (z.oblique)
        e = z.t[std::size_t(k)];
      else
        e[(z.axis + 1 + k) % D] = Real(1);
      const Vec<D> d = Real(h) * e;
      lap += (double(n.dot(inflow(z, x + d, t))) - 2 * u0 + double(n.dot(inflow(z, x - d, t)))) / (h * h);
    }
  }
  const double mu = scene_.laminar_viscosity ? scene_.nu * scene_.rho0 : 0.0;
  double gn = 0;  // the body force along n (hydrostatic part)
  for (int a = 0; a < D; ++a) gn += scene_.gravity[std::size_t(a)] * double(n[a]);
  return scene_.rho0 * (gn - dudt) + mu * lap;
}

template <int D>
void OpenBoundaries<D>::impose(Simulation<D>& sim) {
  auto& f = sim.fields();
  const auto& s = scene_;
  parallel::Domain<D>* dom = sim.domain();
  const std::size_t n = sim.size();
  buffer_idx_.clear();
  const std::int32_t* zone = zone_->data.data();
  for (std::size_t i = 0; i < n; ++i)
    if (zone[i] >= 0) buffer_idx_.push_back(std::uint32_t(i));
  buffers_ = dom ? std::size_t(sim.comm().sum(std::int64_t(buffer_idx_.size()))) : buffer_idx_.size();
  const kernels::AnyKernel<D> W(s.kernel, s.h, s.kernel_l);
  const Real support = W.support();
  const auto eos = sim.eos();
  const double t = sim.time();
  const auto& grid = sim.grid();
  const std::uint32_t* idx = buffer_idx_.data();
  Vec<D>* x = f.x.data.data();
  Vec<D>* v = f.v.data.data();
  Real* rho = f.rho.data.data();
  Real* p = f.p.data.data();
  const Real* mass = f.mass.data.data();
  const std::int32_t* kind = f.kind.data.data();
  // the ghost node: the buffer particle's mirror image across the interface, inside the fluid
  const auto ghost_node = [&](std::size_t i) {
    const Zone& z = zones_[std::size_t(zone[i])];
    if (z.oblique) return Vec<D>(x[i] - Real(2) * z.n.dot(x[i] - z.c) * z.n);  // mirrored across the plane
    Vec<D> xg = x[i];
    xg[z.axis] = Real(2) * z.face - x[i][z.axis];
    return xg;
  };
  const auto needs_fit = [&](std::size_t i) {
    const Zone& z = zones_[std::size_t(zone[i])];
    return z.spec->pressure_extrapolated || !z.inlet;
  };
  // the first-order fit at a ghost node from the fluid particles around it (grid valid; ghosts current)
  const auto fit_at = [&](const Vec<D>& xg, GhostFit<D>& fit) {
    grid.for_each_near(xg, f.x.data, support, [&](std::uint32_t j, const Vec<D>& xgj) {
      if (kind[j] != 0 || zone[j] >= 0) return;
      const auto k = W(xgj.norm());
      if (k.w <= 0) return;
      fit.add(xgj, double(k.w), double(k.grad_factor), double(mass[j]) / double(rho[j]), double(rho[j]), v[j]);
    });
    return fit.solve();
  };
  // several ranks: a ghost node lies up to two zone depths from its buffer particle, beyond the halo, so the
  // rank that owns its cell fits it (all its neighbours are there, in the serial order) and sends the solution
  std::vector<char> remote(buffer_idx_.size(), 0);
  std::vector<FitAnswer<D>> answers(dom ? buffer_idx_.size() : 0);
  if (dom) {
    std::vector<parallel::HaloArray> arrays;  // the fluid's values after the step, and the buffer tags
    parallel::collect_view(sim.current_view(), parallel::kHaloPositions | parallel::kHaloVelocities | parallel::kHaloState,
                           arrays);
    arrays.push_back({zone_->data.data(), sizeof(std::int32_t), zone_->data.size()});
    dom->refresh(arrays);
    auto& comm = sim.comm();
    const int P = comm.size(), me = comm.rank();
    std::vector<std::vector<FitRequest<D>>> req_out(static_cast<std::size_t>(P));
    std::vector<std::vector<std::size_t>> req_of(static_cast<std::size_t>(P));  // which buffer entry each request is
    for (std::size_t b = 0; b < buffer_idx_.size(); ++b) {
      const std::size_t i = idx[b];
      if (!needs_fit(i)) continue;
      const Vec<D> xg = ghost_node(i);
      const int q = dom->partition().owner(dom->cell_of(xg));
      if (q == me) continue;
      remote[b] = 1;
      req_out[std::size_t(q)].push_back({xg});
      req_of[std::size_t(q)].push_back(b);
    }
    std::vector<std::int64_t> counts(static_cast<std::size_t>(P));
    for (int q = 0; q < P; ++q) counts[std::size_t(q)] = std::int64_t(req_out[std::size_t(q)].size());
    const auto in_counts = comm.alltoall(counts);
    std::vector<std::vector<FitRequest<D>>> req_in(static_cast<std::size_t>(P));
    std::vector<parallel::Message> out_m, in_m;
    for (int q = 0; q < P; ++q) {
      auto& o = req_out[std::size_t(q)];
      if (!o.empty()) out_m.push_back({q, reinterpret_cast<std::byte*>(o.data()), o.size() * sizeof(FitRequest<D>)});
      auto& in = req_in[std::size_t(q)];
      in.resize(std::size_t(in_counts[std::size_t(q)]));
      if (!in.empty()) in_m.push_back({q, reinterpret_cast<std::byte*>(in.data()), in.size() * sizeof(FitRequest<D>)});
    }
    comm.exchange(out_m, in_m);
    std::vector<std::vector<FitAnswer<D>>> ans_out(static_cast<std::size_t>(P)), ans_in(static_cast<std::size_t>(P));
    for (int q = 0; q < P; ++q) {
      const auto& in = req_in[std::size_t(q)];
      auto& a = ans_out[std::size_t(q)];
      a.resize(in.size());
      for_each_particle(in.size(), [&](std::size_t k) {  // each answer its own slot
        GhostFit<D> fit{double(support)};
        a[k].ok = fit_at(in[k].xg, fit) ? 1 : 0;
        a[k].pad = 0;
        a[k].sol = fit.solution();
      });
    }
    out_m.clear();
    in_m.clear();
    for (int q = 0; q < P; ++q) {
      auto& o = ans_out[std::size_t(q)];
      if (!o.empty()) out_m.push_back({q, reinterpret_cast<std::byte*>(o.data()), o.size() * sizeof(FitAnswer<D>)});
      auto& in = ans_in[std::size_t(q)];
      in.resize(req_out[std::size_t(q)].size());
      if (!in.empty()) in_m.push_back({q, reinterpret_cast<std::byte*>(in.data()), in.size() * sizeof(FitAnswer<D>)});
    }
    comm.exchange(out_m, in_m);
    for (int q = 0; q < P; ++q)
      for (std::size_t k = 0; k < ans_in[std::size_t(q)].size(); ++k) answers[req_of[std::size_t(q)][k]] = ans_in[std::size_t(q)][k];
  }
  // each buffer particle writes its own slots and reads only fluid particles (never written here)
  for_each_particle(buffer_idx_.size(), [&](std::size_t b) {
    const std::size_t i = idx[b];
    const Zone& z = zones_[std::size_t(zone[i])];
    const bool need_rho = z.spec->pressure_extrapolated;
    const bool need_v = !z.inlet;
    Vec<D> vi = z.inlet ? inflow(z, x[i], t) : v[i];
    Real rhoi = z.rho_prescribed;
    if (z.spec->hydrostatic)  // hydrostatic below the imposed level (DualSPHysics zsurf, Tafuni et al. 2018): p = p_b + rho0 |g_z| (level - z)
      rhoi = eos.density(eos.pb + Real(s.rho0) * z.gz * std::max(Real(0), Real(z.spec->level_at(t)) - x[i][D - 1]));
    if (need_rho || need_v) {
      const Vec<D> xg = ghost_node(i);
      GhostFit<D> fit{double(support)};
      bool ok;
      if (remote[b]) {
        ok = answers[b].ok != 0;
        fit.set_solution(answers[b].sol);
      } else {
        ok = fit_at(xg, fit);
      }
      if (ok) {
        if (need_rho && z.inlet) {
          // an inlet's pressure (issue 32, the wall-corner runaway): the ghost node's value, carried to the buffer
          // particle with the normal gradient of the buffer's own momentum balance, not the fluid's
          // (normal_gradient: the compatibility condition of a prescribed velocity, Gresho & Sani 1987)
          const double dn = double(normal(z).dot(x[i] - xg));
          rhoi = eos.density(Real(double(eos.pressure(Real(fit.value(0)))) + dn * normal_gradient(z, x[i], t)));
        } else if (need_rho) {
          // density to first order: rho_g + (x - x_g) . grad rho_g (Tafuni 2018 eq. 20)
          rhoi = Real(fit.value(0) + fit.gradient(0).dot((x[i] - xg).template cast<double>()));
        }
        // velocity with zero gradient: the ghost node's value (Tafuni 2018 eq. 21)
        if (need_v)
          for (int a = 0; a < D; ++a) vi[a] = Real(fit.value(1 + a));
      }
    }
    v[i] = vi;
    rho[i] = rhoi;
    p[i] = eos.pressure(rhoi);
  });
}

template class OpenBoundaries<2>;
template class OpenBoundaries<3>;

}  // namespace varsph
