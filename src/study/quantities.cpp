#include "study/quantities.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

namespace varsph::study {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRelNoise = 1e-9;  // differences below this fraction of a series' magnitude count as rounding

// Global series taken from diagnostics.csv (sums over fluid particles, CONTRACT.md); total_energy is derived.
const std::vector<std::string> kDiagnosticSeries = {"kinetic_energy", "potential_energy", "total_energy",
                                                    "momentum_x",     "momentum_y",       "momentum_z",
                                                    "max_speed"};

std::string fmt(const char* f, double a, double b = 0) {
  char buf[200];
  std::snprintf(buf, sizeof buf, f, a, b);
  return buf;
}

double largest_magnitude(const Series& s, const Window& w) {
  double m = 0;
  for (std::size_t k = 0; k < s.t.size(); ++k)
    if (s.t[k] >= w.t0 - 1e-12 && s.t[k] <= w.t1 + 1e-12) m = std::max(m, std::abs(s.v[k]));
  return m;
}

std::string quantity_name(const std::string& series, Kind k, const Window& w, Norm n) {
  return series + "." + (k == Kind::Series ? std::string(to_string(n)) : std::string(to_string(k))) + "[" +
         w.label() + "]";
}

// `floor_mag`: the largest magnitude of the vector this series is a component of (0 when it is none)
void scalar_quantity(Quantity& q, const AnalysisInput& in, const std::vector<Series>& s, double floor_mag) {
  const std::size_t L = s.size();
  q.values.assign(L, kNaN);
  double mag = 0, sampling = 0;
  std::vector<int> at_edge, signs;
  for (std::size_t k = 0; k < L; ++k) {
    if (s[k].empty()) continue;
    mag = std::max(mag, largest_magnitude(s[k], q.window));
    q.values[k] = quantity_value(s[k], q.kind, q.window, in.norm);
    if (q.kind == Kind::Peak || q.kind == Kind::PeakTime) {
      const Peak p = peak_of(s[k], q.window.t0, q.window.t1);
      if (p.at_edge) at_edge.push_back(int(k));
      if (std::isfinite(p.value)) signs.push_back(p.value > 0 ? 1 : p.value < 0 ? -1 : 0);
      if (std::isfinite(p.sampling)) sampling = std::max(sampling, p.sampling);
    }
  }
  const double noise = q.kind == Kind::PeakTime ? kRelNoise * (q.window.t1 - q.window.t0)
                                                : kRelNoise * std::max(mag, floor_mag) + 1e-300;
  q.noise = noise;
  q.est = richardson(in.refined, q.values, in.formal_order, noise);
  if (!at_edge.empty()) {
    std::string lv;
    for (int k : at_edge) lv += (lv.empty() ? "L" : ", L") + std::to_string(k);
    q.est.flags.push_back("the largest value lies at the window's edge (" + lv +
                          "): not an interior peak, so peak and time of peak describe the window, not an event");
  }
  if (!signs.empty() && std::any_of(signs.begin(), signs.end(), [&](int v) { return v != signs[0]; }))
    q.est.flags.push_back("the peak changes sign between levels: the levels pick different events");
  if (q.kind == Kind::PeakTime && sampling > 0) {
    double largest = 0;
    for (std::size_t k = 0; k + 1 < L; ++k)
      if (std::isfinite(q.values[k]) && std::isfinite(q.values[k + 1]))
        largest = std::max(largest, std::abs(q.values[k + 1] - q.values[k]));
    if (largest < sampling)
      q.est.flags.push_back(fmt("the peak times differ by less than the sampling interval %.3g s (the parabola "
                                "through the samples refines it, but the order is unreliable): sample finer "
                                "(output.probes_every)", sampling));
  }
  if (!q.est.flags.empty()) q.est.safety = 3.0;
  for (std::size_t k = 0; k < L; ++k)
    if (std::isfinite(q.est.error[k])) q.est.bound[k] = q.est.safety * q.est.error[k];
  const double fine = [&] {
    for (std::size_t k = L; k-- > 0;)
      if (std::isfinite(q.values[k])) return q.values[k];
    return kNaN;
  }();
  q.scale = std::isfinite(q.est.extrapolated) && q.est.extrapolated != 0 ? std::abs(q.est.extrapolated)
                                                                         : std::abs(fine);
}

void series_quantity(Quantity& q, const AnalysisInput& in, const std::vector<Series>& s, double floor_mag) {
  const std::size_t L = s.size();
  std::vector<const Series*> valid;
  for (const auto& x : s)
    if (!x.empty()) valid.push_back(&x);
  q.values.assign(L, kNaN);
  q.grid = common_grid(valid, q.window.t0, q.window.t1);
  q.resampled.assign(L, {});
  double mag = 0;
  for (std::size_t k = 0; k < L; ++k) {
    if (s[k].empty() || q.grid.empty()) continue;
    q.resampled[k] = resample(s[k], q.grid);
    q.values[k] = norm_of(q.resampled[k], in.norm);
    mag = std::max(mag, norm_of(q.resampled[k], Norm::Linf));
  }
  std::vector<double> d(L > 0 ? L - 1 : 0, kNaN);
  for (std::size_t k = 0; k + 1 < L; ++k)
    if (!q.resampled[k].empty() && !q.resampled[k + 1].empty())
      d[k] = norm_of_difference(q.resampled[k], q.resampled[k + 1], in.norm);
  q.noise = kRelNoise * std::max(mag, floor_mag) + 1e-300;
  q.est = richardson_of_differences(in.refined, d, in.formal_order, q.noise);
  for (std::size_t k = 0; k < L; ++k)
    if (q.resampled[k].empty() && L > 0) {
      q.est.flags.push_back("level L" + std::to_string(k) + " has no such series (failed run)");
      break;
    }
  if (!q.est.flags.empty()) q.est.safety = 3.0;
  const std::size_t f = L - 1;
  if (L >= 2 && !q.resampled[f].empty() && !q.resampled[f - 1].empty() && std::isfinite(q.est.order_used)) {
    const double r21 = in.refined[f - 1] / in.refined[f];
    const double c = 1.0 / (std::pow(r21, q.est.order_used) - 1.0);
    q.extrapolated_series.resize(q.grid.size());
    for (std::size_t i = 0; i < q.grid.size(); ++i)
      q.extrapolated_series[i] = q.resampled[f][i] + c * (q.resampled[f][i] - q.resampled[f - 1][i]);
    for (std::size_t k = 0; k < L; ++k)
      if (!q.resampled[k].empty()) q.est.error[k] = norm_of_difference(q.resampled[k], q.extrapolated_series, in.norm);
    q.est.extrapolated = norm_of(q.extrapolated_series, in.norm);
  } else if (L >= 1 && std::isfinite(q.est.error[f]) && !q.resampled[f].empty()) {
    for (std::size_t k = 0; k + 1 < L; ++k)
      if (!q.resampled[k].empty())
        q.est.error[k] = norm_of_difference(q.resampled[k], q.resampled[f], in.norm) + q.est.error[f];
  }
  for (std::size_t k = 0; k < L; ++k)
    if (std::isfinite(q.est.error[k])) q.est.bound[k] = q.est.safety * q.est.error[k];
  q.scale = !q.extrapolated_series.empty() ? norm_of(q.extrapolated_series, in.norm)
                                           : (L ? q.values[L - 1] : kNaN);
}

}  // namespace

std::string Window::label() const {
  char buf[80];
  std::snprintf(buf, sizeof buf, "%g:%g", t0, t1);
  return buf;
}

const char* to_string(Kind k) {
  switch (k) {
    case Kind::Peak: return "peak";
    case Kind::PeakTime: return "t_peak";
    case Kind::Mean: return "mean";
    case Kind::End: return "end";
    case Kind::Series: return "series";
  }
  return "?";
}

void load_run_outputs(LevelRun& r) {
  std::ifstream in(r.dir / "run.json");
  if (in) {
    try {
      nlohmann::json j;
      in >> j;
      r.status = j.value("status", "");
      r.message = j.value("message", "");
      if (j.contains("timings")) {
        r.steps = j["timings"].value("steps", 0L);
        r.solver_wall = j["timings"].value("wall_seconds", 0.0);
      }
      if (j.contains("resolved")) {
        r.spec.fluid = j["resolved"].value("fluid_particles", r.spec.fluid);
        r.spec.boundary = j["resolved"].value("boundary_particles", r.spec.boundary);
      }
    } catch (const std::exception&) {
      r.status = "unreadable run.json";
    }
  }
  r.probes = read_table(r.dir / "probes.csv");
  r.diagnostics = read_table(r.dir / "diagnostics.csv");
}

std::vector<std::string> series_names(const std::vector<const LevelRun*>& runs) {
  std::vector<std::string> out;
  const auto add = [&](const std::string& n) {
    if (std::find(out.begin(), out.end(), n) == out.end()) out.push_back(n);
  };
  for (const LevelRun* r : runs)
    for (const auto& c : r->probes.columns)
      if (c != "time") add(c);
  for (const auto& n : kDiagnosticSeries)
    for (const LevelRun* r : runs)
      if (r->diagnostics.column(n) || (n == "total_energy" && r->diagnostics.column("kinetic_energy"))) {
        if (n == "momentum_z" && r->spec.dimension == 2) continue;
        add(n);
        break;
      }
  return out;
}

Series run_series(const LevelRun& r, const std::string& name) {
  if (r.probes.column(name)) return series_of(r.probes, name);
  if (name == "total_energy") {
    Series s = series_of(r.diagnostics, "kinetic_energy");
    const Series pe = series_of(r.diagnostics, "potential_energy"), ie = series_of(r.diagnostics, "internal_energy");
    if (pe.t.size() != s.t.size() || ie.t.size() != s.t.size()) return {};
    for (std::size_t k = 0; k < s.t.size(); ++k) s.v[k] += pe.v[k] + ie.v[k];
    return s;
  }
  return series_of(r.diagnostics, name);
}

double quantity_value(const Series& s, Kind kind, const Window& w, Norm norm) {
  switch (kind) {
    case Kind::Peak: return peak_of(s, w.t0, w.t1).value;
    case Kind::PeakTime: return peak_of(s, w.t0, w.t1).time;
    case Kind::Mean: return window_mean(s, w.t0, w.t1);
    case Kind::End: return s.empty() ? kNaN : interpolate(s, std::min(w.t1, s.t.back()));
    case Kind::Series: {
      const auto g = common_grid({&s}, w.t0, w.t1);
      return g.empty() ? kNaN : norm_of(resample(s, g), norm);
    }
  }
  return kNaN;
}

double quantity_difference(const Series& a, const Series& b, Kind kind, const Window& w, Norm norm) {
  if (kind != Kind::Series) return std::abs(quantity_value(b, kind, w, norm) - quantity_value(a, kind, w, norm));
  const auto g = common_grid({&a, &b}, w.t0, w.t1);
  return g.empty() ? kNaN : norm_of_difference(resample(a, g), resample(b, g), norm);
}

bool vector_components(const std::string& a, const std::string& b) {
  if (a.size() != b.size() || a == b) return false;
  const auto axis = [](char c) { return c == 'x' || c == 'y' || c == 'z'; };
  std::size_t differ = 0, at = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i]) ++differ, at = i;
  return differ == 1 && axis(a[at]) && axis(b[at]);
}

std::vector<Quantity> analyse(const AnalysisInput& in) {
  std::vector<Quantity> out;
  const std::size_t L = in.levels.size();
  const std::vector<std::string> names = series_names(in.levels);
  std::vector<std::vector<Series>> all(names.size(), std::vector<Series>(L));
  for (std::size_t n = 0; n < names.size(); ++n)
    for (std::size_t k = 0; k < L; ++k)
      if (in.levels[k]->ok()) all[n][k] = run_series(*in.levels[k], names[n]);
  for (std::size_t n = 0; n < names.size(); ++n) {
    const std::string& name = names[n];
    const std::vector<Series>& s = all[n];
    for (const auto& w : in.windows) {
      double floor_mag = 0;  // the vector's largest component in this window
      for (std::size_t m = 0; m < names.size(); ++m)
        if (vector_components(name, names[m]))
          for (const auto& x : all[m]) floor_mag = std::max(floor_mag, largest_magnitude(x, w));
      double own_mag = 0;
      for (const auto& x : s) own_mag = std::max(own_mag, largest_magnitude(x, w));
      // a series whose largest magnitude is at the window's start or end in every level has no peak event
      // (a rising front, a decaying energy): its peak would repeat the end or start value
      bool edge_only = false, any = false;
      for (const auto& x : s)
        if (!x.empty()) {
          const bool e = peak_of(x, w.t0, w.t1).at_edge;
          edge_only = any ? edge_only && e : e;
          any = true;
        }
      for (Kind kind : {Kind::Peak, Kind::PeakTime, Kind::Mean, Kind::End, Kind::Series}) {
        if (edge_only && (kind == Kind::Peak || kind == Kind::PeakTime)) continue;
        Quantity q;
        q.series = name;
        q.kind = kind;
        q.window = w;
        q.name = quantity_name(name, kind, w, in.norm);
        if (kind == Kind::Series) series_quantity(q, in, s, floor_mag);
        else scalar_quantity(q, in, s, floor_mag);
        q.rounding_only = own_mag <= kRelNoise * floor_mag;
        out.push_back(std::move(q));
      }
    }
  }
  return out;
}

}  // namespace varsph::study
