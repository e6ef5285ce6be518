#include "study/tolerance.hpp"

#include <cmath>
#include <cstdlib>

#include "core/errors.hpp"

namespace varsph::study {
namespace {

double parse_value(const std::string& v, const std::string& text, bool& relative) {
  std::string s = v;
  relative = !s.empty() && s.back() == '%';
  if (relative) s.pop_back();
  char* end = nullptr;
  const double x = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0' || !(x > 0) || !std::isfinite(x))
    throw InputError("--tolerance '" + text + "': expected a positive number, a percentage (5%), or "
                     "QUANTITY=VALUE[%] (e.g. 'p_wall.peak[*]=500' or 'front_x.*=1%')");
  return relative ? x / 100.0 : x;
}

}  // namespace

ToleranceSpec parse_tolerance(const std::string& text) {
  ToleranceSpec t;
  t.text = text;
  const auto eq = text.rfind('=');
  if (eq == std::string::npos) {
    t.pattern = "*";
    bool pct = false;
    t.value = parse_value(text, text, pct);
    t.relative = true;  // a bare number is a fraction of each quantity's scale
  } else {
    t.pattern = text.substr(0, eq);
    if (t.pattern.empty()) throw InputError("--tolerance '" + text + "': the quantity name before '=' is empty");
    t.value = parse_value(text.substr(eq + 1), text, t.relative);
  }
  return t;
}

bool matches(const std::string& p, const std::string& s) {
  // glob with '*' only (iterative, backtracking on the last star)
  std::size_t i = 0, j = 0, star = std::string::npos, mark = 0;
  while (j < s.size()) {
    if (i < p.size() && p[i] == s[j]) {
      ++i, ++j;
    } else if (i < p.size() && p[i] == '*') {
      star = i++;
      mark = j;
    } else if (star != std::string::npos) {
      i = star + 1;
      j = ++mark;
    } else {
      return false;
    }
  }
  while (i < p.size() && p[i] == '*') ++i;
  return i == p.size();
}

ToleranceResult evaluate_tolerance(const ToleranceSpec& spec, const std::vector<Quantity>& quantities,
                                   const std::vector<double>& refined, double cost_exponent) {
  ToleranceResult r;
  r.spec = spec;
  const std::size_t L = refined.size();
  int overall = 0;
  bool any = false;
  for (const auto& q : quantities) {
    if (!matches(spec.pattern, q.name)) continue;
    QuantityVerdict v;
    v.quantity = q.name;
    v.tolerance = spec.relative ? spec.value * q.scale : spec.value;
    bool estimated = false;
    for (std::size_t k = 0; k < L && k < q.est.bound.size(); ++k) {
      if (!std::isfinite(q.est.bound[k])) continue;
      estimated = true;
      if (q.est.bound[k] <= v.tolerance) {
        v.cheapest_level = int(k);
        break;
      }
    }
    if (!estimated) {
      ++r.without_estimate;
      r.quantities.push_back(v);
      continue;
    }
    any = true;
    if (v.cheapest_level < 0) {
      overall = -1;
      // bound ~ C h^p: the refined parameter that meets the tolerance, and its cost relative to the finest;
      // only from a trusted order (a flagged one, e.g. p = 0.25 for slow convergence, predicts nonsense)
      const double b = q.est.bound[L - 1], p = q.est.order_used;
      if (q.est.trusted() && std::isfinite(b) && b > 0 && std::isfinite(p) && p > 0) {
        v.needed_refined = refined[L - 1] * std::pow(v.tolerance / b, 1.0 / p);
        v.needed_cost_factor = std::pow(refined[L - 1] / v.needed_refined, cost_exponent);
      }
    } else if (overall >= 0) {
      overall = std::max(overall, v.cheapest_level);
    }
    r.quantities.push_back(v);
  }
  r.cheapest_level = any ? overall : -1;
  return r;
}

}  // namespace varsph::study
