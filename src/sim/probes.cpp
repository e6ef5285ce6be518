#include "sim/probes.hpp"

#include <cmath>
#include <limits>

#include "core/errors.hpp"
#include "kernels/kernel_eval.hpp"
#include "parallel/communicator.hpp"
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

// Shepard-normalised SPH interpolation over fluid neighbours only (walls do not carry fluid pressure):
// p(x) = sum_j (m_j / rho_j) p_j W(x - x_j) / sum_j (m_j / rho_j) W(x - x_j); 0 where no fluid is within
// the support (a dry gauge).
template <int D>
double Probes<D>::pressure_at(const Simulation<D>& sim, const Vec<D>& x) const {
  const auto& f = sim.fields();
  const auto& sc = sim.scene();
  const kernels::AnyKernel<D> W(sc.kernel, sc.h, sc.kernel_l);
  const Real rc = W.support();
  double num = 0, den = 0;
  for (std::size_t j = 0; j < sim.size(); ++j) {  // serial, storage order
    if (f.kind[j] != 0) continue;
    const Real r = (x - f.x[j]).norm();
    if (r >= rc) continue;
    const double w = double(f.mass[j]) / double(f.rho[j]) * double(W(r).w);
    num += w * double(f.p[j]);
    den += w;
  }
  if (sim.distributed()) {  // sums over every rank's particles
    double nd[2] = {num, den};
    sim.comm().sum(nd);
    num = nd[0];
    den = nd[1];
  }
  return den > 0 ? num / den : 0.0;
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
  if (sim.distributed()) sim.comm().sum(phis);  // sums over every rank's particles
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
std::vector<double> Probes<D>::sample(const Simulation<D>& sim) {
  std::vector<double> out;
  const auto& f = sim.fields();
  bool forces_done = false;
  for (const auto& p : specs_) {
    if (p.type == "pressure") {
      Vec<D> x;
      for (int a = 0; a < D; ++a) x[a] = Real(p.point[a]);
      out.push_back(pressure_at(sim, x));
    } else if (p.type == "water_height") {
      out.push_back(water_height(sim, p));
    } else if (p.type == "front") {
      double xf = -std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < sim.size(); ++i)
        if (f.kind[i] == 0) xf = std::max(xf, double(f.x[i][0]));
      out.push_back(sim.global_max(xf));
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
      if (sim.distributed()) {  // sums over every rank's boundary particles
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

template class Probes<2>;
template class Probes<3>;

}  // namespace varsph
