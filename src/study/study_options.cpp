#include "study/study_options.hpp"

#include <cmath>
#include <cstdlib>

#include "core/errors.hpp"

namespace varsph::study {

Refine parse_refine(const std::string& s) {
  if (s == "dx") return Refine::Dx;
  if (s == "dt") return Refine::Dt;
  if (s == "both") return Refine::Both;
  throw InputError("--refine: expected dx, dt or both, got '" + s + "'");
}

const char* to_string(Refine r) { return r == Refine::Dx ? "dx" : r == Refine::Dt ? "dt" : "both"; }

double parse_ratio(const std::string& s) {
  if (s == "sqrt2") return std::sqrt(2.0);
  char* end = nullptr;
  const double r = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0' || !(r > 1.05) || !(r <= 4))
    throw InputError("--ratio: expected 2, sqrt2 or a number in (1.05, 4], got '" + s + "'");
  return r;
}

Window parse_window(const std::string& s) {
  const auto c = s.find(':');
  Window w;
  char* e0 = nullptr;
  char* e1 = nullptr;
  if (c != std::string::npos) {
    const std::string a = s.substr(0, c), b = s.substr(c + 1);
    w.t0 = std::strtod(a.c_str(), &e0);
    w.t1 = std::strtod(b.c_str(), &e1);
    if (!a.empty() && !b.empty() && *e0 == '\0' && *e1 == '\0' && w.t1 > w.t0 && w.t0 >= 0) return w;
  }
  throw InputError("--window: expected T0:T1 in seconds with 0 <= T0 < T1 (e.g. 0.2:0.6), got '" + s + "'");
}

}  // namespace varsph::study
