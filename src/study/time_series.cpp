#include "study/time_series.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/errors.hpp"

namespace varsph::study {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::stringstream ss(line);
  while (std::getline(ss, cell, ',')) {
    const auto b = cell.find_first_not_of(" \t\r"), e = cell.find_last_not_of(" \t\r");
    out.push_back(b == std::string::npos ? std::string() : cell.substr(b, e - b + 1));
  }
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

double median_interval(const std::vector<double>& t) {
  if (t.size() < 2) return kNaN;
  std::vector<double> d;
  for (std::size_t k = 1; k < t.size(); ++k) d.push_back(t[k] - t[k - 1]);
  std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
  return d[d.size() / 2];
}

}  // namespace

const std::vector<double>* Table::column(const std::string& name) const {
  for (std::size_t k = 0; k < columns.size(); ++k)
    if (columns[k] == name) return &data[k];
  return nullptr;
}

Table read_table(const std::filesystem::path& path) {
  Table t;
  std::ifstream in(path);
  if (!in) return t;
  std::string line;
  long lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line[0] == '#') continue;
    if (t.columns.empty()) {
      t.columns = split_csv(line);
      t.data.assign(t.columns.size(), {});
      continue;
    }
    const auto cells = split_csv(line);
    if (cells.size() > t.columns.size())
      throw InputError(path.string() + ":" + std::to_string(lineno) + ": expected at most " +
                       std::to_string(t.columns.size()) + " cells (the header's), got " + std::to_string(cells.size()));
    // a short last row is a row the run was writing when it stopped: ignored
    if (cells.size() < t.columns.size() && in.peek() == EOF) break;
    for (std::size_t k = 0; k < t.columns.size(); ++k) {
      double v = kNaN;
      if (k < cells.size() && !cells[k].empty()) {
        char* end = nullptr;
        v = std::strtod(cells[k].c_str(), &end);
        if (end == cells[k].c_str()) v = kNaN;
      }
      t.data[k].push_back(v);
    }
  }
  return t;
}

Series series_of(const Table& table, const std::string& name) {
  Series s;
  const auto* t = table.column("time");
  const auto* v = table.column(name);
  if (!t || !v) return s;
  for (std::size_t k = 0; k < t->size(); ++k)
    if (std::isfinite((*t)[k]) && std::isfinite((*v)[k]) && (s.t.empty() || (*t)[k] > s.t.back())) {
      s.t.push_back((*t)[k]);
      s.v.push_back((*v)[k]);
    }
  return s;
}

Norm parse_norm(const std::string& s) {
  if (s == "l1") return Norm::L1;
  if (s == "l2") return Norm::L2;
  if (s == "linf") return Norm::Linf;
  throw InputError("--norm: expected l1, l2 or linf, got '" + s + "'");
}

const char* to_string(Norm n) { return n == Norm::L1 ? "l1" : n == Norm::L2 ? "l2" : "linf"; }

double interpolate(const Series& s, double t) {
  if (s.t.empty() || t < s.t.front() - 1e-12 * std::abs(s.t.front()) - 1e-15 ||
      t > s.t.back() + 1e-12 * std::abs(s.t.back()) + 1e-15)
    return kNaN;
  auto it = std::upper_bound(s.t.begin(), s.t.end(), t);
  if (it == s.t.begin()) return s.v.front();
  if (it == s.t.end()) return s.v.back();
  const std::size_t k = std::size_t(it - s.t.begin());
  const double a = (t - s.t[k - 1]) / (s.t[k] - s.t[k - 1]);
  return (1 - a) * s.v[k - 1] + a * s.v[k];
}

std::vector<double> resample(const Series& s, const std::vector<double>& grid) {
  std::vector<double> out(grid.size());
  for (std::size_t k = 0; k < grid.size(); ++k) out[k] = interpolate(s, grid[k]);
  return out;
}

std::vector<double> common_grid(const std::vector<const Series*>& levels, double t0, double t1) {
  double lo = t0, hi = t1, dt = 0;
  for (const Series* s : levels) {
    if (!s || s->t.size() < 2) return {};
    lo = std::max(lo, s->t.front());
    hi = std::min(hi, s->t.back());
    dt = std::max(dt, median_interval(s->t));
  }
  if (!(hi > lo) || !(dt > 0)) return {};
  const long n = std::max(2L, long(std::floor((hi - lo) / dt + 1e-9)) + 1);
  std::vector<double> g(static_cast<std::size_t>(n));
  for (long k = 0; k < n; ++k) g[std::size_t(k)] = lo + (hi - lo) * double(k) / double(n - 1);
  return g;
}

Peak peak_of(const Series& s, double t0, double t1) {
  Peak p;
  p.sampling = median_interval(s.t);
  std::size_t best = s.t.size(), first = s.t.size(), last = 0;
  for (std::size_t k = 0; k < s.t.size(); ++k) {
    if (s.t[k] < t0 - 1e-12 || s.t[k] > t1 + 1e-12) continue;
    first = std::min(first, k);
    last = k;
    if (best == s.t.size() || std::abs(s.v[k]) > std::abs(s.v[best])) best = k;
  }
  if (best == s.t.size()) return p;
  p.value = s.v[best];
  p.time = s.t[best];
  p.at_edge = best == first || best == last;
  if (!p.at_edge) {
    // vertex of the parabola through the three samples (non-uniform spacing allowed)
    const double x0 = s.t[best - 1], x1 = s.t[best], x2 = s.t[best + 1];
    const double y0 = s.v[best - 1], y1 = s.v[best], y2 = s.v[best + 1];
    const double d0 = (y1 - y0) / (x1 - x0), d1 = (y2 - y1) / (x2 - x1);
    const double a = (d1 - d0) / (x2 - x0);
    if (a != 0) {
      const double tv = 0.5 * (x0 + x1) - d0 / (2 * a);
      if (tv > x0 && tv < x2) p.time = tv;
    }
  }
  return p;
}

double window_mean(const Series& s, double t0, double t1) {
  const double lo = std::max(t0, s.t.empty() ? t0 : s.t.front());
  const double hi = std::min(t1, s.t.empty() ? t1 : s.t.back());
  if (s.t.size() < 2 || !(hi >= lo)) return kNaN;
  if (hi == lo) return interpolate(s, lo);
  std::vector<double> ts = {lo};
  for (double t : s.t)
    if (t > lo && t < hi) ts.push_back(t);
  ts.push_back(hi);
  double area = 0;
  double prev = interpolate(s, ts[0]);
  for (std::size_t k = 1; k < ts.size(); ++k) {
    const double cur = interpolate(s, ts[k]);
    area += 0.5 * (prev + cur) * (ts[k] - ts[k - 1]);
    prev = cur;
  }
  return area / (hi - lo);
}

double norm_of_difference(const std::vector<double>& a, const std::vector<double>& b, Norm n) {
  double acc = 0;
  std::size_t cnt = 0;
  for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k) {
    const double d = std::abs(a[k] - b[k]);
    if (!std::isfinite(d)) continue;
    ++cnt;
    if (n == Norm::L1) acc += d;
    else if (n == Norm::L2) acc += d * d;
    else acc = std::max(acc, d);
  }
  if (cnt == 0) return kNaN;
  if (n == Norm::L1) return acc / double(cnt);
  if (n == Norm::L2) return std::sqrt(acc / double(cnt));
  return acc;
}

double norm_of(const std::vector<double>& a, Norm n) {
  return norm_of_difference(a, std::vector<double>(a.size(), 0.0), n);
}

}  // namespace varsph::study
