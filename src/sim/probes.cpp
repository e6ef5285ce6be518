#include "sim/probes.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "core/errors.hpp"
#include "kernels/kernel_eval.hpp"
#include "parallel/communicator.hpp"
#include "physics/corrected_interpolation.hpp"
#include "scene/json_reader.hpp"

namespace varsph {

std::vector<ProbeSpec> parse_probes(const scene::Scene& s) {
  const int d = s.dimension;
  // validate through the scene reader so messages read "FILE: key 'probes.N.key': expected ..."
  nlohmann::json root = nlohmann::json::object();
  root["probes"] = s.probes;
  scene::JsonReader r(std::move(root), s.file.string());
  std::vector<ProbeSpec> out;
  const std::size_t n = r.array_size("probes");
  for (std::size_t k = 0; k < n; ++k) {
    const std::string base = "probes." + std::to_string(k) + ".";
    ProbeSpec p;
    if (!r.raw("probes." + std::to_string(k))->is_object())
      r.fail_got("probes." + std::to_string(k), "a probe object {\"type\": ..., \"name\": ...}",
                 *r.raw("probes." + std::to_string(k)));
    p.type = r.choice(base + "type", std::nullopt, {"pressure", "water_height", "front", "force"});
    p.name = r.text(base + "name", p.type == "front" ? std::optional<std::string>("") : std::nullopt);
    for (char c : p.name)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
        r.fail_got(base + "name", "a name of letters, digits and '_' (it becomes a column name)", p.name);
    if (p.name.empty() && p.type != "front") r.fail(base + "name", "a non-empty name");
    for (const auto& q : out)
      if (q.type == p.type && q.name == p.name) r.fail_got(base + "name", "a name not used by another probe of this type", p.name);
    if (p.type == "pressure") {
      p.point = r.vector(base + "point", d, std::nullopt, "probe position [m]");
      p.radius = r.number(base + "radius", 0.0, 0.0, std::numeric_limits<double>::infinity(),
                          "radius of the sensor face [m]");
      if (r.raw(base + "normal")) {
        p.normal = r.vector(base + "normal", d, std::nullopt, "sensor face normal pointing into the fluid");
        double len = 0;
        for (double c : p.normal) len += c * c;
        if (!(len > 0)) r.fail_got(base + "normal", "a non-zero vector", *r.raw(base + "normal"));
        for (double& c : p.normal) c /= std::sqrt(len);
      }
    } else if (p.type == "water_height") {
      p.point = r.vector(base + "from", d, std::nullopt, "lower end of the vertical gauge line [m]");
      p.top = r.number(base + "to", s.domain_max[d - 1], p.point[d - 1], std::numeric_limits<double>::infinity(),
                       "upper end of the gauge line (vertical coordinate) [m]");
    } else if (p.type == "force") {
      p.body = int(r.integer(base + "body", std::nullopt, 0, long(s.bodies.size()) - 1));
      if (s.bodies[std::size_t(p.body)].kind != "boundary")
        r.fail_got(base + "body", "the index of a boundary body (bodies." + std::to_string(p.body) + " is fluid)",
                   p.body);
      p.moment_about = r.vector(base + "moment_about", d, std::vector<double>(d, 0.0), "moment reference point [m]");
    }
    out.push_back(std::move(p));
  }
  r.check_unknown();
  return out;
}

template <int D>
Probes<D>::Probes(const scene::Scene& s) : specs_(parse_probes(s)) {}

template <int D>
std::vector<std::string> Probes<D>::columns() const {
  std::vector<std::string> c;
  const char* axes[3] = {"x", "y", "z"};
  for (const auto& p : specs_) {
    if (p.type == "pressure") c.push_back("p_" + p.name);
    if (p.type == "water_height") c.push_back("h_" + p.name);
    if (p.type == "front") c.push_back(p.name.empty() ? "front_x" : "front_x_" + p.name);
    if (p.type == "force") {
      for (int a = 0; a < D; ++a) c.push_back(std::string("F") + axes[a] + "_" + p.name);
      if (D == 2) c.push_back("Mz_" + p.name);
      else
        for (int a = 0; a < 3; ++a) c.push_back(std::string("M") + axes[a] + "_" + p.name);
    }
  }
  return c;
}

// The fluid pressure at a point x (a face with normal n, or n = 0 inside the fluid), first-order consistent (physics/corrected_interpolation.hpp) over
// the fluid particles within the kernel support: exact for a linear field (hydrostatic) even on a
// wall, where half the support holds no fluid; Shepard where ill conditioned; 0 where dry.
// On a face with normal n the linear fit is centred half a spacing inside the fluid, x + (dx/2) n, where
// the support is better filled (condition number ~13 instead of ~70 on the face itself), and evaluated on
// the face: p = p_node - (dx/2) n . grad p_node.
template <int D>
double Probes<D>::fluid_pressure(const Simulation<D>& sim, const Vec<D>& x, const Vec<D>& n) const {
  const auto& f = sim.fields();
  const auto& sc = sim.scene();
  const kernels::AnyKernel<D> W(sc.kernel, sc.h, sc.kernel_l);
  const Real off = Real(0.5 * sc.spacing);
  const Vec<D> node = x + off * n;
  // distributed runs: the rank owning the node's cell has every neighbour (own or ghost) in the serial
  // order and computes the serial value; the others add 0 (an exact sum)
  double value = 0.0;
  if (sim.owns_point(node)) {
    physics::CorrectedInterpolation<D> interp(double(W.support()));
    sim.grid().for_each_near(node, f.x.data, W.support(), [&](std::uint32_t j, const Vec<D>& xgj) {
      if (f.kind[j] != 0) return;
      const auto k = W(xgj.norm());
      interp.add(xgj, double(k.w), double(k.grad_factor), double(f.mass[j]) / double(f.rho[j]), double(f.p[j]));
    });
    const auto r = interp.solve();
    if (!r.empty) value = r.value - double(off) * r.gradient.dot(n.template cast<double>());
  }
  return sim.distributed() ? sim.global_sum(value) : value;
}

// What a wall pressure transducer reads (the one definition for every case and wall model): the mean
// of the fluid-side pressure over its face, a disc of `radius` (a segment in 2D) centred on `point` and
// normal to the face normal, by a Gauss rule (2D: 3 points; 3D: the 7-point disc rule, degree 5;
// Abramowitz & Stegun 25.4.61). radius 0: the point value. Time averaging: see sample().
template <int D>
double Probes<D>::pressure_at(const Simulation<D>& sim, const ProbeSpec& p, std::size_t k) const {
  Vec<D> c;
  for (int a = 0; a < D; ++a) c[a] = Real(p.point[a]);
  const Vec<D>& n = normals_[k];
  if (!(p.radius > 0) || n.squaredNorm() == 0) return fluid_pressure(sim, c, n);
  const Real r = Real(p.radius);
  if constexpr (D == 2) {
    const Vec<D> t(-n[1], n[0]);
    const Real q = r * Real(std::sqrt(0.6));
    return (5.0 * fluid_pressure(sim, Vec<D>(c - q * t), n) + 8.0 * fluid_pressure(sim, c, n) +
            5.0 * fluid_pressure(sim, Vec<D>(c + q * t), n)) / 18.0;
  } else {
    Vec<D> t1 = std::abs(n[0]) < Real(0.9) ? Vec<D>(Vec<D>::UnitX()) : Vec<D>(Vec<D>::UnitY());
    t1 = (t1 - t1.dot(n) * n).normalized();
    const Vec<D> t2 = n.cross(t1);
    const Real q = r * Real(std::sqrt(2.0 / 3.0));
    double sum = 0.25 * fluid_pressure(sim, c, n);
    for (int m = 0; m < 6; ++m) {
      const double th = m * std::numbers::pi / 3.0;
      sum += 0.125 * fluid_pressure(sim, Vec<D>(c + q * (Real(std::cos(th)) * t1 + Real(std::sin(th)) * t2)), n);
    }
    return sum;
  }
}

// A sensor face without a given normal takes the normal of the nearest boundary particle within two
// spacings of its centre (a face on a wall); none there: a point sensor (an error when a radius is set).
template <int D>
void Probes<D>::resolve_normals(const Simulation<D>& sim) {
  if (normals_resolved_) return;
  normals_resolved_ = true;
  const auto& f = sim.fields();
  normals_.assign(specs_.size(), Vec<D>::Zero());
  for (std::size_t k = 0; k < specs_.size(); ++k) {
    const auto& p = specs_[k];
    if (p.type != "pressure") continue;
    if (!p.normal.empty()) {
      for (int a = 0; a < D; ++a) normals_[k][a] = Real(p.normal[std::size_t(a)]);
      continue;
    }
    Vec<D> c;
    for (int a = 0; a < D; ++a) c[a] = Real(p.point[a]);
    double best = 4.0 * sim.scene().spacing * sim.scene().spacing;
    for (std::size_t i = 0; i < sim.size(); ++i) {  // once, at the start
      if (f.kind[i] == 0 || f.normal[i].squaredNorm() == 0) continue;
      const double d2 = double((f.x[i] - c).squaredNorm());
      if (d2 < best) {
        best = d2;
        normals_[k] = f.normal[i];
      }
    }
    if (sim.distributed()) {  // the nearest over every rank (ties: the lowest rank's candidate)
      const double global_best = -sim.global_max(-best);
      const int mine = best == global_best && normals_[k].squaredNorm() > 0 ? sim.comm().rank() : sim.comm().size();
      const int winner = int(-sim.global_max(-double(mine)));
      for (int a = 0; a < D; ++a) {
        const double v = sim.global_sum(sim.comm().rank() == winner ? double(normals_[k][a]) : 0.0);
        normals_[k][a] = Real(v);
      }
    }
    if (p.radius > 0 && normals_[k].squaredNorm() == 0)
      throw InputError(sim.scene().file.string() + ": probe '" + p.name +
                       "' has a radius but no `normal` and no wall particle within two spacings of its point: "
                       "give probes.N.normal (the face normal pointing into the fluid)");
  }
}

// Water height on a vertical line: the fluid indicator phi(y) = sum_j (m_j / rho_j) W (about 1 inside
// the fluid, 0 outside, 1/2 at the free surface) is sampled every dx/4 from `from` up to `to`; the
// height is the highest level where phi crosses 1/2 (linear interpolation), measured from `from`.
template <int D>
double Probes<D>::water_height(const Simulation<D>& sim, const ProbeSpec& p) const {
  const auto& f = sim.fields();
  const auto& sc = sim.scene();
  const kernels::AnyKernel<D> W(sc.kernel, sc.h, sc.kernel_l);
  const Real rc = W.support();
  Vec<D> base;
  for (int a = 0; a < D; ++a) base[a] = Real(p.point[a]);
  // fluid particles near the line (horizontal distance below the support)
  std::vector<std::size_t> near;
  for (std::size_t j = 0; j < sim.size(); ++j) {
    if (f.kind[j] != 0) continue;
    Vec<D> dxy = f.x[j] - base;
    dxy[D - 1] = 0;
    if (dxy.norm() < rc) near.push_back(j);
  }
  const double step = sc.spacing / 4;
  const double y0 = p.point[D - 1];
  const long m = long(std::ceil((p.top - y0) / step));
  std::vector<double> phis(std::size_t(m + 1), 0.0);
  for (long k = 0; k <= m; ++k) {
    Vec<D> x = base;
    x[D - 1] = Real(std::min(y0 + double(k) * step, p.top));
    double phi = 0;
    for (std::size_t j : near) {
      const Real r = (x - f.x[j]).norm();
      if (r < rc) phi += double(f.mass[j]) / double(f.rho[j]) * double(W(r).w);
    }
    phis[std::size_t(k)] = phi;
  }
  if (sim.distributed()) sim.comm().sum(phis);  // sums over every rank's particles (to round-off)
  double h = 0, prev_phi = 0, prev_y = y0;
  for (long k = 0; k <= m; ++k) {
    const double y = std::min(y0 + double(k) * step, p.top);
    const double phi = phis[std::size_t(k)];
    if (k > 0 && prev_phi >= 0.5 && phi < 0.5) h = prev_y + (prev_phi - 0.5) / (prev_phi - phi) * (y - prev_y) - y0;
    if (k == m && phi >= 0.5) h = y - y0;  // filled to the top of the line
    prev_phi = phi;
    prev_y = y;
  }
  return h;
}

template <int D>
std::vector<double> Probes<D>::loads(const Simulation<D>& sim) {
  resolve_normals(sim);
  std::vector<double> out;
  const auto& f = sim.fields();
  bool forces_done = false;
  for (std::size_t k = 0; k < specs_.size(); ++k) {
    const auto& p = specs_[k];
    if (p.type == "pressure") {
      out.push_back(pressure_at(sim, p, k));
    } else if (p.type == "force") {
      if (!forces_done) {  // one reaction pass for all force probes
        force_.assign(sim.store().size(), Vec<D>::Zero());  // the pass may touch ghost slots
        sim.rates().boundary_reaction(sim.grid(), sim.current_view(), force_.data());
        forces_done = true;
      }
      double F[3] = {0, 0, 0}, M[3] = {0, 0, 0};
      for (std::size_t i = 0; i < sim.size(); ++i) {  // serial sums in storage order
        if (f.kind[i] == 0 || f.body[i] != p.body) continue;
        double fi[3] = {0, 0, 0}, ri[3] = {0, 0, 0};
        for (int a = 0; a < D; ++a) {
          fi[a] = double(force_[i][a]);
          ri[a] = double(f.x[i][a]) - p.moment_about[std::size_t(a)];
          F[a] += fi[a];
        }
        M[0] += ri[1] * fi[2] - ri[2] * fi[1];
        M[1] += ri[2] * fi[0] - ri[0] * fi[2];
        M[2] += ri[0] * fi[1] - ri[1] * fi[0];
      }
      if (sim.distributed()) {  // sums over every rank's boundary particles (to round-off)
        sim.comm().sum(F);
        sim.comm().sum(M);
      }
      for (int a = 0; a < D; ++a) out.push_back(F[a]);
      if (D == 2) out.push_back(M[2]);
      else out.insert(out.end(), {M[0], M[1], M[2]});
    }
  }
  return out;
}

template <int D>
void Probes<D>::accumulate(const Simulation<D>& sim) {
  const std::vector<double> now = loads(sim);
  if (sum_.size() != now.size()) sum_.assign(now.size(), 0.0);
  const double dt = sim.dt();
  for (std::size_t c = 0; c < now.size(); ++c) sum_[c] += now[c] * dt;
  window_ += dt;
}

template <int D>
std::vector<double> Probes<D>::sample(const Simulation<D>& sim) {
  std::vector<double> load = window_ > 0 ? sum_ : loads(sim);
  if (window_ > 0)
    for (double& v : load) v /= window_;
  sum_.assign(load.size(), 0.0);
  window_ = 0;
  std::vector<double> out;
  const auto& f = sim.fields();
  std::size_t next_load = 0;
  for (const auto& p : specs_) {
    if (p.type == "pressure") {
      out.push_back(load[next_load++]);
    } else if (p.type == "force") {
      const std::size_t n = D == 2 ? 3 : 6;
      out.insert(out.end(), load.begin() + long(next_load), load.begin() + long(next_load + n));
      next_load += n;
    } else if (p.type == "water_height") {
      out.push_back(water_height(sim, p));
    } else if (p.type == "front") {
      double xf = -std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < sim.size(); ++i)
        if (f.kind[i] == 0) xf = std::max(xf, double(f.x[i][0]));
      out.push_back(sim.distributed() ? sim.global_max(xf) : xf);
    }
  }
  return out;
}

template <int D>
nlohmann::json Probes<D>::save_state() const {
  return {{"sum", sum_}, {"window", window_}};
}

template <int D>
void Probes<D>::restore_state(const nlohmann::json& j) {
  if (!j.is_object()) return;
  sum_ = j.value("sum", std::vector<double>{});
  window_ = j.value("window", 0.0);
}

template class Probes<2>;
template class Probes<3>;

}  // namespace varsph
