#pragma once
// Internal: a uniform hash grid over 3D points (2D points use z = 0), insert-only, linked lists.
#include <Eigen/Core>
#include <cmath>
#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace varsph::geometry::detail {

class PointGrid {
 public:
  explicit PointGrid(double cell) : inv_(1.0 / cell) { head_.reserve(1024); }
  void reserve(std::size_t n) { head_.reserve(n); next_.reserve(n); pts_.reserve(n); }
  int insert(const Eigen::Vector3d& p) {
    const int id = static_cast<int>(pts_.size());
    pts_.push_back(p);
    auto [it, fresh] = head_.try_emplace(key(cell_of(p)), id);
    next_.push_back(fresh ? -1 : it->second);
    if (!fresh) it->second = id;
    return id;
  }
  const Eigen::Vector3d& point(int i) const { return pts_[i]; }
  std::size_t size() const { return pts_.size(); }
  // true if a stored point lies strictly closer than r (r <= cell size) to p. With r <= cell/2 only
  // the 2x2x2 block of cells on p's side of its cell can hold such a point.
  bool any_within(const Eigen::Vector3d& p, double r) const {
    const double r2 = r * r;
    if (r * inv_ <= 0.5) {
      const Eigen::Vector3d f = p * inv_;
      const Eigen::Vector3i c = cell_of(p);
      Eigen::Vector3i lo;
      for (int a = 0; a < 3; ++a) lo[a] = (f[a] - c[a] < 0.5) ? c[a] - 1 : c[a];
      for (int dx = 0; dx < 2; ++dx)
        for (int dy = 0; dy < 2; ++dy)
          for (int dz = 0; dz < 2; ++dz) {
            auto it = head_.find(key(lo + Eigen::Vector3i(dx, dy, dz)));
            if (it == head_.end()) continue;
            for (int i = it->second; i >= 0; i = next_[i])
              if ((pts_[i] - p).squaredNorm() < r2) return true;
          }
      return false;
    }
    bool found = false;
    for_cells(p, 1, [&](int i) {
      if (!found && (pts_[i] - p).squaredNorm() < r2) found = true;
    });
    return found;
  }
  // distance to the nearest stored point if it is within one cell size, else infinity
  double distance_within(const Eigen::Vector3d& p) const {
    double bd = INFINITY;
    for_cells(p, 1, [&](int i) { bd = std::min(bd, (pts_[i] - p).squaredNorm()); });
    return std::sqrt(bd) * inv_ <= 1.0 ? std::sqrt(bd) : INFINITY;
  }
  // index of the nearest stored point (-1 if empty)
  int nearest(const Eigen::Vector3d& p) const {
    if (pts_.empty()) return -1;
    int best = -1;
    double bd = INFINITY;
    for (int ring = 1; ring <= 4; ++ring) {
      for_cells(p, ring, [&](int i) {
        const double d = (pts_[i] - p).squaredNorm();
        if (d < bd) { bd = d; best = i; }
      });
      // a point found within `ring` cells is certainly the nearest if closer than ring cells
      if (best >= 0 && std::sqrt(bd) * inv_ <= ring) return best;
    }
    for (std::size_t i = 0; i < pts_.size(); ++i) {
      const double d = (pts_[i] - p).squaredNorm();
      if (d < bd) { bd = d; best = static_cast<int>(i); }
    }
    return best;
  }

 private:
  Eigen::Vector3i cell_of(const Eigen::Vector3d& p) const {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() * inv_)),
                           static_cast<int>(std::floor(p.y() * inv_)),
                           static_cast<int>(std::floor(p.z() * inv_)));
  }
  static std::uint64_t key(const Eigen::Vector3i& c) {
    auto u = [](int v) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v + (1 << 20)) & 0x1FFFFF); };
    return (u(c.x()) << 42) | (u(c.y()) << 21) | u(c.z());
  }
  template <class F>
  void for_cells(const Eigen::Vector3d& p, int ring, F&& f) const {
    const Eigen::Vector3i c = cell_of(p);
    for (int dx = -ring; dx <= ring; ++dx)
      for (int dy = -ring; dy <= ring; ++dy)
        for (int dz = -ring; dz <= ring; ++dz) {
          auto it = head_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == head_.end()) continue;
          for (int i = it->second; i >= 0; i = next_[i]) f(i);
        }
  }
  double inv_;
  std::unordered_map<std::uint64_t, int> head_;
  std::vector<int> next_;
  std::vector<Eigen::Vector3d> pts_;
};

}  // namespace varsph::geometry::detail
