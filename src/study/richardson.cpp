#include "study/richardson.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace varsph::study {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string fmt(const char* f, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

// How the three finest levels behave and what may be done with them.
struct Classified {
  double p = kNaN;       // observed order (signed before the monotone check)
  double p_used = kNaN;  // order for extrapolation; NaN: no extrapolation (range fallback)
  bool no_change = false;
  double safety = 3.0;
  std::vector<std::string> flags, notes;
};

Classified classify(double e21, double e32, double r21, double r32, double formal, double noise, bool signs_known) {
  Classified c;
  const bool small21 = std::abs(e21) <= noise, small32 = std::abs(e32) <= noise;
  if (small21 && small32) {
    c.no_change = true;
    c.safety = 1.25;
    c.notes.push_back("no change between the levels beyond rounding (converged, or insensitive to resolution)");
    return c;
  }
  if (small21) {
    c.flags.push_back("the two finest levels agree to rounding while the coarser one differs: order not "
                      "measurable (coincidence or a discrete effect); error taken as the largest difference");
    return c;
  }
  if (signs_known && e21 * e32 < 0) {
    c.p = three_level_order(e21, e32, r21, r32);
    c.flags.push_back("oscillatory (non-monotone) convergence: the level differences change sign; no "
                      "extrapolation, error taken as the largest difference");
    return c;
  }
  c.p = three_level_order(e21, e32, r21, r32);
  if (!(c.p > 0)) {
    c.flags.push_back(fmt("differences grow under refinement (order %.2f): not converging at these levels; "
                          "error taken as the largest difference", c.p));
    return c;
  }
  if (c.p < 0.5) {
    c.p_used = std::max(c.p, 0.25);
    c.flags.push_back(fmt("observed order %.2f is below 0.5, far from the scheme's %.3g: convergence too slow "
                          "for a reliable extrapolation", c.p, formal));
  } else if (c.p > formal + 1.0) {
    c.p_used = formal;
    c.flags.push_back(fmt("observed order %.2f is far above the scheme's %.3g (errors may cancel): "
                          "extrapolated with the formal order", c.p, formal));
  } else {
    c.p_used = std::min(c.p, formal);
    c.safety = 1.25;
  }
  return c;
}

}  // namespace

double three_level_order(double e21, double e32, double r21, double r32) {
  // Celik et al. 2008, eq. (3): fixed-point iteration on q(p) = ln((r21^p - s)/(r32^p - s)); q = 0 for equal
  // ratios, where p = ln|e32/e21| / ln r21 (Richardson's three-level order).
  const double s = (e32 / e21) >= 0 ? 1.0 : -1.0;
  const double lr = std::log(std::abs(e32 / e21));
  double p = lr / std::log(r21);
  if (std::abs(r21 - r32) < 1e-12 * r21) return p;
  for (int it = 0; it < 100; ++it) {
    const double pa = std::abs(p);
    const double num = std::pow(r21, pa) - s, den = std::pow(r32, pa) - s;
    const double q = (num > 0 && den > 0) ? std::log(num / den) : 0.0;
    const double next = (lr + q) / std::log(r21);
    if (std::abs(next - p) < 1e-10) return next;
    p = next;
  }
  return p;
}

double log_log_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t k = 0; k < std::min(x.size(), y.size()); ++k) {
    if (!(x[k] > 0) || !(y[k] > 0) || !std::isfinite(x[k]) || !std::isfinite(y[k])) continue;
    const double a = std::log(x[k]), b = std::log(y[k]);
    sx += a, sy += b, sxx += a * a, sxy += a * b, ++n;
  }
  if (n < 2) return kNaN;
  const double den = n * sxx - sx * sx;
  return den > 0 ? (n * sxy - sx * sy) / den : kNaN;
}

OrderEstimate richardson(const std::vector<double>& h, const std::vector<double>& phi, double formal, double noise) {
  OrderEstimate e;
  const std::size_t L = std::min(h.size(), phi.size());
  e.error.assign(L, kNaN);
  e.bound.assign(L, kNaN);
  std::vector<std::size_t> v;  // levels with a value, coarsest first
  for (std::size_t k = 0; k < L; ++k)
    if (std::isfinite(phi[k])) v.push_back(k);
  if (v.size() < L) e.flags.push_back(std::to_string(L - v.size()) + " level(s) without a value (failed runs)");
  if (v.size() < 2) {
    e.flags.push_back("fewer than two levels: no error estimate");
    return e;
  }
  // orders of every consecutive triple and the least-squares slope of the differences
  std::vector<double> hx, dy;
  for (std::size_t j = 0; j + 1 < v.size(); ++j) {
    hx.push_back(h[v[j]]);
    dy.push_back(std::abs(phi[v[j + 1]] - phi[v[j]]));
  }
  e.order_fit = log_log_slope(hx, dy);
  for (std::size_t j = 0; j + 2 < v.size(); ++j) {
    const double e21 = phi[v[j + 1]] - phi[v[j + 2]], e32 = phi[v[j]] - phi[v[j + 1]];
    e.orders.push_back(std::abs(e21) > noise ? three_level_order(e21, e32, h[v[j + 1]] / h[v[j + 2]],
                                                                 h[v[j]] / h[v[j + 1]])
                                             : kNaN);
  }
  const std::size_t f = v.back(), m = v[v.size() - 2];
  const double r21 = h[m] / h[f];
  const double e21 = phi[m] - phi[f];
  double range = std::abs(e21);  // largest difference among the levels used, for the fallback
  Classified c;
  if (v.size() == 2) {
    c.p_used = formal;
    c.flags.push_back("two levels only: no observed order; error from the scheme's formal order");
    if (std::abs(e21) <= noise) c.notes.push_back("no change between the two levels beyond rounding");
  } else {
    const std::size_t co = v[v.size() - 3];
    const double e32 = phi[co] - phi[m];
    range = std::max(range, std::abs(e32));
    c = classify(e21, e32, r21, h[co] / h[m], formal, noise, true);
    if (e.orders.size() >= 2) {
      const double a = e.orders[e.orders.size() - 2], b = e.orders.back();
      if (std::isfinite(a) && std::isfinite(b) && std::abs(a - b) > 0.5)
        c.flags.push_back(fmt("orders of successive level triples differ (%.2f, then %.2f): the levels are not "
                              "yet in the asymptotic range", a, b));
    }
  }
  e.order = c.p;
  e.order_used = c.p_used;
  e.safety = c.flags.empty() ? c.safety : 3.0;
  e.flags.insert(e.flags.end(), c.flags.begin(), c.flags.end());
  e.notes = c.notes;
  if (c.no_change) {
    e.extrapolated = phi[f];
    for (std::size_t k : v) e.error[k] = std::abs(phi[k] - phi[f]) + noise;
  } else if (std::isfinite(c.p_used)) {
    // Richardson: phi_ext = phi1 + (phi1 - phi2) / (r21^p - 1)
    e.extrapolated = phi[f] + (phi[f] - phi[m]) / (std::pow(r21, c.p_used) - 1.0);
    for (std::size_t k : v) e.error[k] = std::abs(phi[k] - e.extrapolated);
  } else {
    // no trustworthy extrapolation: the finest level's error is the largest level difference
    for (std::size_t k : v) e.error[k] = std::abs(phi[k] - phi[f]) + range;
  }
  for (std::size_t k : v) e.bound[k] = e.safety * e.error[k];
  return e;
}

OrderEstimate richardson_of_differences(const std::vector<double>& h, const std::vector<double>& d, double formal,
                                        double noise) {
  OrderEstimate e;
  const std::size_t L = h.size();
  e.error.assign(L, kNaN);
  e.bound.assign(L, kNaN);
  if (L < 2 || d.size() + 1 < L || !std::isfinite(d[L - 2])) {
    e.flags.push_back("fewer than two levels with this series: no error estimate");
    return e;
  }
  std::vector<double> hx(h.begin(), h.begin() + long(L - 1));
  e.order_fit = log_log_slope(hx, std::vector<double>(d.begin(), d.begin() + long(L - 1)));
  for (std::size_t j = 0; j + 2 < L; ++j)
    e.orders.push_back(d[j + 1] > noise ? three_level_order(d[j + 1], d[j], h[j + 1] / h[j + 2], h[j] / h[j + 1])
                                        : kNaN);
  const double r21 = h[L - 2] / h[L - 1], d21 = d[L - 2];
  Classified c;
  double range = d21;
  if (L == 2 || !std::isfinite(d[L - 3])) {
    c.p_used = formal;
    c.flags.push_back("two levels only: no observed order; error from the scheme's formal order");
  } else {
    range = std::max(range, d[L - 3]);
    c = classify(d21, d[L - 3], r21, h[L - 3] / h[L - 2], formal, noise, false);
    if (e.orders.size() >= 2) {
      const double a = e.orders[e.orders.size() - 2], b = e.orders.back();
      if (std::isfinite(a) && std::isfinite(b) && std::abs(a - b) > 0.5)
        c.flags.push_back(fmt("orders of successive level triples differ (%.2f, then %.2f): the levels are not "
                              "yet in the asymptotic range", a, b));
    }
  }
  e.order = c.p;
  e.order_used = c.p_used;
  e.safety = c.flags.empty() ? c.safety : 3.0;
  e.flags.insert(e.flags.end(), c.flags.begin(), c.flags.end());
  e.notes = c.notes;
  if (c.no_change) e.error[L - 1] = d21 + noise;
  else if (std::isfinite(c.p_used)) e.error[L - 1] = d21 / (std::pow(r21, c.p_used) - 1.0);
  else e.error[L - 1] = range;
  e.bound[L - 1] = e.safety * e.error[L - 1];
  return e;
}

}  // namespace varsph::study
