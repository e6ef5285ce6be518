#pragma once
// Mesh writers and brute-force checks shared by the geometry tests.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdio>
#include <vector>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

namespace vt {

using Eigen::MatrixXd;
using Eigen::MatrixXi;
using Eigen::Vector3d;

// fresh directory for one test's files
inline std::filesystem::path temp_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  auto d = std::filesystem::path(VARSPH_BINARY_DIR) / "test_tmp" / "geometry" /
           (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

// cube [0,L]^3, 8 vertices, 12 outward triangles
inline void cube(double L, MatrixXd& V, MatrixXi& F) {
  V.resize(8, 3);
  for (int i = 0; i < 8; ++i) V.row(i) << ((i & 1) ? L : 0), ((i & 2) ? L : 0), ((i & 4) ? L : 0);
  const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  F.resize(12, 3);
  for (int f = 0; f < 6; ++f) {
    F.row(2 * f) << q[f][0], q[f][1], q[f][2];
    F.row(2 * f + 1) << q[f][0], q[f][2], q[f][3];
  }
}

// icosphere of radius R centred at c, `level` subdivisions (20 * 4^level outward triangles)
inline void icosphere(double R, int level, MatrixXd& V, MatrixXi& F, Vector3d c = Vector3d::Zero()) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                             {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<Eigen::Vector3i> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                    {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (auto& p : v) p.normalize();
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto m = [&](int a, int b) {
      auto k = std::minmax(a, b);
      auto it = mid.find(k);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[k] = static_cast<int>(v.size()) - 1;
    };
    std::vector<Eigen::Vector3i> g;
    for (auto& tr : f) {
      const int a = m(tr[0], tr[1]), b = m(tr[1], tr[2]), cc = m(tr[2], tr[0]);
      g.push_back({tr[0], a, cc}); g.push_back({tr[1], b, a}); g.push_back({tr[2], cc, b}); g.push_back({a, b, cc});
    }
    f = g;
  }
  V.resize(static_cast<int>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) V.row(static_cast<int>(i)) = (c + R * v[i]).transpose();
  F.resize(static_cast<int>(f.size()), 3);
  for (std::size_t i = 0; i < f.size(); ++i) F.row(static_cast<int>(i)) = f[i].transpose();
}

inline void write_off(const std::filesystem::path& p, const MatrixXd& V, const MatrixXi& F) {
  std::ofstream o(p);
  o.precision(17);
  o << "OFF\n" << V.rows() << " " << F.rows() << " 0\n";
  for (int i = 0; i < V.rows(); ++i) o << V(i, 0) << " " << V(i, 1) << " " << V(i, 2) << "\n";
  for (int i = 0; i < F.rows(); ++i) o << "3 " << F(i, 0) << " " << F(i, 1) << " " << F(i, 2) << "\n";
}

inline Vector3d fnormal(const MatrixXd& V, const MatrixXi& F, int f) {
  const Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
  return (b - a).cross(c - a).normalized();
}

inline void write_stl_ascii(const std::filesystem::path& p, const MatrixXd& V, const MatrixXi& F) {
  std::ofstream o(p);
  o.precision(17);
  o << "solid cube\n";
  for (int f = 0; f < F.rows(); ++f) {
    const Vector3d n = fnormal(V, F, f);
    o << " facet normal " << n.x() << " " << n.y() << " " << n.z() << "\n  outer loop\n";
    for (int c = 0; c < 3; ++c) o << "   vertex " << V(F(f, c), 0) << " " << V(F(f, c), 1) << " " << V(F(f, c), 2) << "\n";
    o << "  endloop\n endfacet\n";
  }
  o << "endsolid cube\n";
}

inline void write_stl_binary(const std::filesystem::path& p, const MatrixXd& V, const MatrixXi& F) {
  std::ofstream o(p, std::ios::binary);
  char header[80] = {};
  std::snprintf(header, sizeof header, "binary cube");
  o.write(header, 80);
  const std::uint32_t n = static_cast<std::uint32_t>(F.rows());
  o.write(reinterpret_cast<const char*>(&n), 4);
  for (int f = 0; f < F.rows(); ++f) {
    const Vector3d nn = fnormal(V, F, f);
    float buf[12] = {float(nn.x()), float(nn.y()), float(nn.z())};
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) buf[3 + 3 * c + k] = static_cast<float>(V(F(f, c), k));
    o.write(reinterpret_cast<const char*>(buf), sizeof buf);
    const std::uint16_t attr = 0;
    o.write(reinterpret_cast<const char*>(&attr), 2);
  }
}

inline void write_obj(const std::filesystem::path& p, const MatrixXd& V, const MatrixXi& F) {
  std::ofstream o(p);
  o.precision(17);
  o << "# cube\n";
  for (int i = 0; i < V.rows(); ++i) o << "v " << V(i, 0) << " " << V(i, 1) << " " << V(i, 2) << "\n";
  for (int f = 0; f < F.rows(); ++f) o << "f " << F(f, 0) + 1 << " " << F(f, 1) + 1 << " " << F(f, 2) + 1 << "\n";
}

inline void write_ply(const std::filesystem::path& p, const MatrixXd& V, const MatrixXi& F) {
  std::ofstream o(p);
  o.precision(17);
  o << "ply\nformat ascii 1.0\nelement vertex " << V.rows() << "\nproperty double x\nproperty double y\nproperty double z\n"
    << "element face " << F.rows() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < V.rows(); ++i) o << V(i, 0) << " " << V(i, 1) << " " << V(i, 2) << "\n";
  for (int f = 0; f < F.rows(); ++f) o << "3 " << F(f, 0) << " " << F(f, 1) << " " << F(f, 2) << "\n";
}

// closest distance from p to triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5)
inline double point_triangle_distance(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  const Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double den = 1.0 / (va + vb + vc);
  return (p - (a + ab * vb * den + ac * vc * den)).norm();
}

inline double mesh_distance(const Vector3d& p, const MatrixXd& V, const MatrixXi& F) {
  double d = INFINITY;
  for (int f = 0; f < F.rows(); ++f)
    d = std::min(d, point_triangle_distance(p, V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2))));
  return d;
}

// smallest distance between two rows of X (uniform grid, cell size h)
inline double min_pair_distance(const MatrixXd& X, double h) {
  std::map<std::array<long, 3>, std::vector<int>> grid;
  auto cell = [&](int i) {
    std::array<long, 3> c{0, 0, 0};
    for (int k = 0; k < X.cols(); ++k) c[k] = static_cast<long>(std::floor(X(i, k) / h));
    return c;
  };
  for (int i = 0; i < X.rows(); ++i) grid[cell(i)].push_back(i);
  double best = INFINITY;
  for (int i = 0; i < X.rows(); ++i) {
    const auto c = cell(i);
    for (long a = -1; a <= 1; ++a)
      for (long b = -1; b <= 1; ++b)
        for (long d = -1; d <= 1; ++d) {
          auto it = grid.find({c[0] + a, c[1] + b, c[2] + d});
          if (it == grid.end()) continue;
          for (int j : it->second)
            if (j > i) best = std::min(best, (X.row(i) - X.row(j)).norm());
        }
  }
  return best;
}

// rows sorted lexicographically (to compare point sets)
inline MatrixXd sorted_rows(const MatrixXd& X) {
  std::vector<int> idx(X.rows());
  for (int i = 0; i < X.rows(); ++i) idx[i] = i;
  std::sort(idx.begin(), idx.end(), [&](int a, int b) {
    for (int k = 0; k < X.cols(); ++k)
      if (X(a, k) != X(b, k)) return X(a, k) < X(b, k);
    return false;
  });
  MatrixXd Y(X.rows(), X.cols());
  for (int i = 0; i < X.rows(); ++i) Y.row(i) = X.row(idx[i]);
  return Y;
}

inline bool has_note(const std::vector<std::string>& notes, const std::string& word) {
  for (const auto& n : notes)
    if (n.find(word) != std::string::npos) return true;
  return false;
}

}  // namespace vt
