#include "varsph/geometry/sample_curves.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "detail/sample_selection.h"

namespace varsph::geometry {
namespace {
using detail::WeightedPoints;
using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kCornerTurn = 30.0 * M_PI / 180.0;  // a vertex turning more than this is a corner
constexpr double kCandidatesPerDx = 8;

Vector3d lift(const Vector2d& p) { return Vector3d(p.x(), p.y(), 0.0); }
Vector2d right_normal(const Vector2d& t) { return Vector2d(t.y(), -t.x()).normalized(); }

double point_segment_distance(const Vector2d& p, const Vector2d& a, const Vector2d& b) {
  const Vector2d ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

struct Seg { Vector2d a, b, n; };

}  // namespace

void sample_curves(const std::vector<Polyline2>& lines, double dx, int layers, int side,
                   Eigen::MatrixXd& X, Eigen::MatrixXd& N, Eigen::VectorXd& A, Eigen::VectorXi& L) {
  const double s = side >= 0 ? 1.0 : -1.0;
  const double h = dx / kCandidatesPerDx;
  // repeated consecutive points (zero-length segments) removed
  std::vector<Polyline2> clean = lines;
  for (auto& l : clean) {
    std::vector<Vector2d> q;
    for (Eigen::Index i = 0; i < l.P.rows(); ++i) {
      const Vector2d p = l.P.row(i).transpose();
      if (q.empty() || (p - q.back()).norm() > 1e-12 * dx) q.push_back(p);
    }
    if (l.closed && q.size() > 1 && (q.front() - q.back()).norm() <= 1e-12 * dx) q.pop_back();
    l.P.resize(static_cast<Eigen::Index>(q.size()), 2);
    for (std::size_t i = 0; i < q.size(); ++i) l.P.row(static_cast<Eigen::Index>(i)) = q[i].transpose();
  }
  std::vector<Seg> segs;  // all segments, for distances
  // layer 0 points (fixed) with a flag "on a straight piece" (pushed as fixed points in layers > 0)
  WeightedPoints base;
  std::vector<char> base_straight;
  // curved pieces, candidates for offset layers: (polyline, segment) pairs
  std::vector<std::pair<int, int>> curved_segs;
  for (int li = 0; li < static_cast<int>(lines.size()); ++li) {
    const auto& line = clean[li];
    const int nv = static_cast<int>(line.P.rows());
    if (nv < 2) continue;
    const bool closed = line.closed && nv >= 3;
    const int ns = closed ? nv : nv - 1;
    const std::size_t line_begin = base.size();
    std::vector<std::pair<int, double>> pending_half;
    std::vector<Vector2d> P(nv);
    for (int i = 0; i < nv; ++i) P[i] = line.P.row(i).transpose();
    std::vector<Vector2d> sn(ns);
    std::vector<double> slen(ns);
    for (int i = 0; i < ns; ++i) {
      const Vector2d t = P[(i + 1) % nv] - P[i];
      slen[i] = t.norm();
      sn[i] = slen[i] > 0 ? right_normal(t) : Vector2d(0, 0);
      segs.push_back({P[i], P[(i + 1) % nv], sn[i]});
    }
    // corners: ends of open polylines and vertices turning more than kCornerTurn
    std::vector<char> corner(nv, 0);
    for (int i = 0; i < nv; ++i) {
      if (!closed && (i == 0 || i == nv - 1)) { corner[i] = 1; continue; }
      const Vector2d& n0 = sn[(i - 1 + ns) % ns];
      const Vector2d& n1 = sn[i % ns];
      corner[i] = std::acos(std::clamp(n0.dot(n1), -1.0, 1.0)) > kCornerTurn;
    }
    int start = -1;
    for (int i = 0; i < nv; ++i)
      if (corner[i]) { start = i; break; }
    // vertex normals inside pieces: average of the two segment normals
    auto vnormal = [&](int i) {
      const Vector2d m = sn[(i - 1 + ns) % ns] + sn[i % ns];
      return m.norm() > 0 ? Vector2d(m.normalized()) : sn[i % ns];
    };
    // walk the pieces; a piece runs from vertex `first` over `count` segments
    std::vector<std::pair<int, int>> pieces;
    if (start < 0) {
      pieces.push_back({0, ns});
    } else {
      int i = start;
      int done = 0;
      while (done < ns) {
        int count = 0;
        int j = i;
        do { j = (j + 1) % nv; ++count; } while (!corner[j] && done + count < ns);
        pieces.push_back({i, count});
        done += count;
        i = j;
      }
    }
    for (const auto& [first, count] : pieces) {
      double len = 0;
      bool straight = true;
      for (int c = 0; c < count; ++c) {
        const int sgi = (first + c) % ns;
        len += slen[sgi];
        if (sn[sgi].dot(sn[first % ns]) < 1.0 - 1e-10) straight = false;
      }
      if (!straight)
        for (int c = 0; c < count; ++c) curved_segs.push_back({li, (first + c) % ns});
      if (len <= 0) continue;
      const int m = std::max(1, static_cast<int>(std::lround(len / dx)));
      const double step = len / m;
      const bool whole_loop = start < 0;
      const bool last_end = !closed && ((first + count) == nv - 1);
      // points at arc length j*step, j = 0..m (the end point only where nobody else places it)
      int sgi = 0;
      double seg_start = 0;
      for (int j = 0; j <= m; ++j) {
        if (j == m && !last_end) break;
        const double sarc = std::min(j * step, len);
        while (sgi < count - 1 && seg_start + slen[(first + sgi) % ns] < sarc - 1e-12 * len) {
          seg_start += slen[(first + sgi) % ns];
          ++sgi;
        }
        const int g = (first + sgi) % ns;
        const double t = slen[g] > 0 ? std::clamp((sarc - seg_start) / slen[g], 0.0, 1.0) : 0.0;
        const Vector2d p = P[g] + t * (P[(g + 1) % nv] - P[g]);
        Vector2d n;
        double w = step;
        if (j == 0 && !whole_loop) {
          // a corner (or an open end): normal = mean of both sides, share = half of each interval
          const int vi = first;
          if (!closed && vi == 0) { n = sn[0]; w = 0.5 * step; }
          else {
            n = vnormal(vi);
            w = 0.5 * step;  // the other half comes from the previous piece (pending_half)
          }
        } else if (j == m) {
          n = sn[(nv - 2)];
          w = 0.5 * step;
        } else {
          // inside a piece: interpolate vertex normals, one-sided at the piece's corners
          const Vector2d na = (sgi == 0 && !whole_loop) ? sn[g] : vnormal(g);
          const Vector2d nb = (sgi == count - 1 && !whole_loop) ? sn[g] : vnormal((g + 1) % nv);
          n = ((1 - t) * na + t * nb).normalized();
        }
        base.add(lift(p), lift(n), w);
        base_straight.push_back(straight && !(j == 0 && !whole_loop));
      }
      // the corner at the end of this piece gets the other half interval (once it exists)
      if (!whole_loop && !last_end) pending_half.push_back({(first + count) % nv, 0.5 * step});
    }
    for (const auto& [vend, half] : pending_half)
      for (std::size_t q = line_begin; q < base.size(); ++q)
        if ((base.x[q] - lift(P[vend])).squaredNorm() == 0.0) { base.w[q] += half; break; }
  }

  std::vector<Vector3d> xs, ns3;
  std::vector<double> as;
  std::vector<int> ls;
  for (int k = 0; k < layers; ++k) {
    const double off = k * dx;
    auto keep = [&](const Vector2d& p) {
      if (k == 0) return true;
      double d = INFINITY;
      for (const auto& sg : segs) d = std::min(d, point_segment_distance(p, sg.a, sg.b));
      return std::abs(d - off) <= 1e-3 * dx;
    };
    WeightedPoints fixed, cand, none;
    if (k == 0) {
      fixed = base;
    } else {
      for (std::size_t i = 0; i < base.size(); ++i) {
        if (!base_straight[i]) continue;
        const Vector2d p = base.x[i].head<2>() + s * off * base.n[i].head<2>();
        if (keep(p)) fixed.add(lift(p), base.n[i], base.w[i]);
      }
      // candidates in walking order: curved segments pushed along their normal, arcs at vertices
      for (int li = 0; li < static_cast<int>(clean.size()); ++li) {
        const auto& line = clean[li];
        const int nv = static_cast<int>(line.P.rows());
        if (nv < 2) continue;
        const bool closed = line.closed && nv >= 3;
        const int ns = closed ? nv : nv - 1;
        auto seg_normal = [&](int i) { return right_normal(line.P.row((i + 1) % nv).transpose() - line.P.row(i).transpose()); };
        for (int i = 0; i < ns; ++i) {
          // arc around vertex i (between segment i-1 and segment i)
          if (closed || i > 0) {
            const Vector2d n0 = s * seg_normal((i - 1 + ns) % ns), n1 = s * seg_normal(i);
            double a0 = std::atan2(n0.y(), n0.x()), a1 = std::atan2(n1.y(), n1.x());
            double da = a1 - a0;
            while (da > M_PI) da -= 2 * M_PI;
            while (da < -M_PI) da += 2 * M_PI;
            const double arc = std::abs(da) * off;
            if (arc > 1e-9 * dx) {
              const int ma = std::max(1, static_cast<int>(std::ceil(arc / h)));
              const Vector2d pv = line.P.row(i).transpose();
              for (int q = 0; q < ma; ++q) {
                const double ang = a0 + (q + 0.5) / ma * da;
                const Vector2d dir(std::cos(ang), std::sin(ang));
                const Vector2d p = pv + off * dir;
                if (keep(p)) cand.add(lift(p), lift(s * dir), arc / ma);
              }
            }
          }
          const bool is_curved = std::find(curved_segs.begin(), curved_segs.end(), std::make_pair(li, i)) != curved_segs.end();
          if (!is_curved) continue;
          const Vector2d a = line.P.row(i).transpose(), b = line.P.row((i + 1) % nv).transpose();
          const double len = (b - a).norm();
          const int m = std::max(1, static_cast<int>(std::ceil(len / h)));
          const Vector2d n = seg_normal(i);
          for (int q = 0; q < m; ++q) {
            const Vector2d p = a + (q + 0.5) / m * (b - a) + s * off * n;
            if (keep(p)) cand.add(lift(p), lift(n), len / m);
          }
        }
      }
    }
    const detail::Layer layer = detail::select_samples(fixed, cand, none, dx, 1, 0.55 * dx, false);
    for (std::size_t i = 0; i < layer.x.size(); ++i) {
      xs.push_back(layer.x[i]); ns3.push_back(layer.n[i]); as.push_back(layer.a[i]); ls.push_back(k);
    }
  }
  const Eigen::Index n = static_cast<Eigen::Index>(xs.size());
  X.resize(n, 2); N.resize(n, 2); A.resize(n); L.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    X.row(i) = xs[i].head<2>().transpose(); N.row(i) = ns3[i].head<2>().transpose(); A[i] = as[i]; L[i] = ls[i];
  }
}

}  // namespace varsph::geometry
