#pragma once
// Internal: turns fixed points, candidate points and area parcels into one layer of particles.
#include <Eigen/Core>
#include <vector>

namespace varsph::geometry::detail {

// A set of weighted points with unit normals (2D uses z = 0).
struct WeightedPoints {
  std::vector<Eigen::Vector3d> x, n;
  std::vector<double> w;  // area [m^2] (3D) or length [m] (2D) each point stands for
  void add(const Eigen::Vector3d& p, const Eigen::Vector3d& nn, double ww) {
    x.push_back(p); n.push_back(nn); w.push_back(ww);
  }
  std::size_t size() const { return x.size(); }
};

struct Layer {
  std::vector<Eigen::Vector3d> x, n;
  std::vector<double> a;
};

// 1. fixed points are kept in order unless closer than fixed_min_distance to a kept one (then their
//    weight becomes a parcel);
// 2. candidates are thinned by dart throwing (in the given order or a fixed pseudo-random order):
//    a candidate is kept if no kept point lies closer than r; r in [0.7 dx, 2 dx] is bisected so
//    that the number kept is round(sum of candidate weights / dx^manifold_dim) within 0.5 % or 1;
// 3. every candidate and parcel gives its weight (and weighted normal) to the nearest kept point.
Layer select_samples(const WeightedPoints& fixed, const WeightedPoints& candidates,
                     const WeightedPoints& parcels, double dx, int manifold_dim,
                     double fixed_min_distance, bool random_order);

}  // namespace varsph::geometry::detail
