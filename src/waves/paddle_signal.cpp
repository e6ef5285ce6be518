#include "waves/paddle_signal.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "waves/wave_theory.hpp"

namespace varsph::waves {

double PaddleGeometry::transfer(double k) const {
  return flap ? flap_transfer(k, depth, hinge_height) : piston_transfer(k * depth);
}

std::vector<Component> regular_waves(const PaddleGeometry& p, double H, double T, double phase, int order) {
  const double omega = 2 * std::numbers::pi / T;
  const double k = wave_number(omega, p.depth, p.g);
  const double stroke = H / p.transfer(k);  // S = H / (H/S)
  std::vector<Component> c{{stroke / 2, omega, phase}};
  if (order == 2) {
    if (p.flap) throw std::invalid_argument("Madsen's second-order correction is for a piston");
    c.push_back({madsen_second_order_amplitude(H, k, p.depth), 2 * omega, 2 * phase});
  }
  return c;
}

void spectrum_bins(const SpectrumSpec& s, std::vector<double>& f, std::vector<double>& a, double& df) {
  const double fp = 1 / s.Tp;
  const double f0 = s.f_min > 0 ? s.f_min : 0.5 * fp, f1 = s.f_max > 0 ? s.f_max : 3 * fp;
  const int n = std::max(s.components, 1);
  df = (f1 - f0) / n;
  const Jonswap S(s.Hs, s.Tp, s.gamma);
  f.resize(std::size_t(n));
  a.resize(std::size_t(n));
  for (int i = 0; i < n; ++i) {
    f[std::size_t(i)] = f0 + (i + 0.5) * df;
    a[std::size_t(i)] = std::sqrt(2 * S(f[std::size_t(i)]) * df);  // a_i^2 / 2 = S df
  }
}

double discrete_m0(const SpectrumSpec& s) {
  std::vector<double> f, a;
  double df = 0;
  spectrum_bins(s, f, a, df);
  double m0 = 0;
  for (double ai : a) m0 += ai * ai / 2;
  return m0;
}

std::vector<Component> irregular_waves(const PaddleGeometry& p, const SpectrumSpec& s) {
  std::vector<double> f, a;
  double df = 0;
  spectrum_bins(s, f, a, df);
  SeededUniform u(s.seed);
  std::vector<Component> c(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    const double omega = 2 * std::numbers::pi * f[i];
    const double k = wave_number(omega, p.depth, p.g);
    c[i] = {a[i] / p.transfer(k), omega, 2 * std::numbers::pi * u.next()};  // random phase, same seed same sea
  }
  return c;
}

std::vector<Component> focused_group(const PaddleGeometry& p, const SpectrumSpec& s, double crest, double x_focus,
                                     double t_focus) {
  std::vector<double> f, a;
  double df = 0;
  spectrum_bins(s, f, a, df);
  double sum = 0;
  for (double ai : a) sum += ai * ai;  // proportional to S(f_i) df
  std::vector<Component> c(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    const double omega = 2 * std::numbers::pi * f[i];
    const double k = wave_number(omega, p.depth, p.g);
    const double ai = crest * a[i] * a[i] / sum;  // NewWave amplitudes (Tromans et al. 1991): sum a_i = A
    c[i] = {ai / p.transfer(k), omega, k * x_focus - omega * t_focus};
  }
  return c;
}

PaddleSignal PaddleSignal::sines(std::vector<Component> c) {
  PaddleSignal s;
  s.comps_ = std::move(c);
  return s;
}

PaddleSignal PaddleSignal::table(std::vector<double> t, std::vector<double> q) {
  if (t.size() != q.size() || t.size() < 2) throw std::invalid_argument("needs at least two (time, value) rows");
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (!std::isfinite(t[i]) || !std::isfinite(q[i]))
      throw std::invalid_argument("row " + std::to_string(i + 1) + ": not a finite number");
    if (i > 0 && !(t[i] > t[i - 1]))
      throw std::invalid_argument("row " + std::to_string(i + 1) + ": time " + std::to_string(t[i]) +
                                  " does not increase (previous " + std::to_string(t[i - 1]) + ")");
  }
  PaddleSignal s;
  s.tt_ = std::move(t);
  s.tq_ = std::move(q);
  return s;
}

PaddleSignal PaddleSignal::read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("cannot read " + path);
  std::vector<double> t, q;
  std::string line;
  int no = 0;
  while (std::getline(in, line)) {
    ++no;
    if (line.empty() || line[0] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ls(line);
    std::string a, b;
    if (!(ls >> a >> b)) throw std::invalid_argument(path + ":" + std::to_string(no) + ": expected two columns");
    char* end = nullptr;
    const double ta = std::strtod(a.c_str(), &end);
    const bool numeric = end != a.c_str();
    if (!numeric && t.empty()) continue;  // a header line
    const double qb = std::strtod(b.c_str(), &end);
    if (!numeric || !std::isfinite(ta) || !std::isfinite(qb) || end == b.c_str())
      throw std::invalid_argument(path + ":" + std::to_string(no) + ": not a finite number: " + line);
    if (!t.empty() && !(ta > t.back()))
      throw std::invalid_argument(path + ":" + std::to_string(no) + ": time " + a + " does not increase");
    t.push_back(ta);
    q.push_back(qb);
  }
  try {
    return table(std::move(t), std::move(q));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
}

PaddleState PaddleSignal::at(double t) const {
  PaddleState s;
  if (t < 0) t = 0;
  if (!tt_.empty()) {
    if (t <= tt_.front()) {
      s.q = tq_.front();
    } else if (t >= tt_.back()) {
      s.q = tq_.back();
    } else {
      const auto k = std::size_t(std::upper_bound(tt_.begin(), tt_.end(), t) - tt_.begin()) - 1;
      const double slope = (tq_[k + 1] - tq_[k]) / (tt_[k + 1] - tt_[k]);
      s.q = tq_[k] + slope * (t - tt_[k]);
      s.dq = slope;
    }
  }
  for (const auto& c : comps_) {
    const double ph = c.omega * t + c.phase;
    s.q += c.amplitude * std::sin(ph);
    s.dq += c.amplitude * c.omega * std::cos(ph);
    s.ddq -= c.amplitude * c.omega * c.omega * std::sin(ph);
  }
  if (ramp_ > 0 && t < ramp_) {
    const double w = std::numbers::pi / ramp_;
    const double r = (1 - std::cos(w * t)) / 2, dr = w * std::sin(w * t) / 2, ddr = w * w * std::cos(w * t) / 2;
    s = {r * s.q, r * s.dq + dr * s.q, r * s.ddq + 2 * dr * s.dq + ddr * s.q};
  }
  return s;
}

double PaddleSignal::max_abs() const {
  double m = 0;
  for (double v : tq_) m = std::max(m, std::abs(v));
  double sum = 0;
  for (const auto& c : comps_) sum += std::abs(c.amplitude);
  return m + sum;
}

}  // namespace varsph::waves
