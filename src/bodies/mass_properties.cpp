#include "bodies/mass_properties.hpp"

#include <cmath>
#include <numbers>

#include <Eigen/Dense>

namespace varsph::bodies {

MassProperties box_mass(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double density, int dim) {
  MassProperties m;
  const Eigen::Vector3d e = hi - lo;
  m.com = 0.5 * (lo + hi);
  if (dim == 2) {
    m.com.z() = 0;
    m.mass = density * e.x() * e.y();
    m.inertia(2, 2) = m.mass * (e.x() * e.x() + e.y() * e.y()) / 12;  // rectangle about its centre
    return m;
  }
  m.mass = density * e.x() * e.y() * e.z();
  m.inertia.diagonal() << m.mass * (e.y() * e.y() + e.z() * e.z()) / 12, m.mass * (e.x() * e.x() + e.z() * e.z()) / 12,
      m.mass * (e.x() * e.x() + e.y() * e.y()) / 12;
  return m;
}

MassProperties ball_mass(const Eigen::Vector3d& center, double radius, double density, int dim) {
  MassProperties m;
  m.com = center;
  const double r2 = radius * radius;
  if (dim == 2) {
    m.com.z() = 0;
    m.mass = density * std::numbers::pi * r2;
    m.inertia(2, 2) = 0.5 * m.mass * r2;  // disc
    return m;
  }
  m.mass = density * 4.0 / 3.0 * std::numbers::pi * r2 * radius;
  m.inertia = Eigen::Matrix3d::Identity() * (0.4 * m.mass * r2);  // ball: 2/5 M R^2
  return m;
}

MassProperties cylinder_mass(const Eigen::Vector3d& center, double radius, const Eigen::Vector3d& axis,
                             double length, double density, int dim) {
  if (dim == 2) return ball_mass(center, radius, density, 2);
  MassProperties m;
  m.com = center;
  const double r2 = radius * radius;
  m.mass = density * std::numbers::pi * r2 * length;
  const Eigen::Vector3d a = axis.normalized();
  const double I_axis = 0.5 * m.mass * r2, I_perp = m.mass * (3 * r2 + length * length) / 12;
  m.inertia = I_perp * Eigen::Matrix3d::Identity() + (I_axis - I_perp) * a * a.transpose();
  return m;
}

MassProperties triangle_mesh_mass(const std::vector<Eigen::Vector3d>& V, const std::vector<Eigen::Vector3i>& F,
                                  double density) {
  // canonical covariance of the tetrahedron (0, e1, e2, e3): integral of x x^T over it
  Eigen::Matrix3d C0;
  C0 << 2, 1, 1, 1, 2, 1, 1, 1, 2;
  C0 /= 120.0;
  double vol = 0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  // moments about a point inside the bounding box keep the sums well conditioned far from the origin
  Eigen::Vector3d o = Eigen::Vector3d::Zero();
  for (const auto& v : V) o += v;
  if (!V.empty()) o /= double(V.size());
  for (const auto& f : F) {
    Eigen::Matrix3d A;
    A.col(0) = V[std::size_t(f[0])] - o;
    A.col(1) = V[std::size_t(f[1])] - o;
    A.col(2) = V[std::size_t(f[2])] - o;
    const double det = A.determinant();  // 6 x the signed volume of (o, a, b, c)
    vol += det / 6;
    first += det / 24 * (A.col(0) + A.col(1) + A.col(2));
    C += det * A * C0 * A.transpose();
  }
  MassProperties m;
  m.mass = density * vol;
  const Eigen::Vector3d c = first / vol;  // relative to o
  m.com = o + c;
  const Eigen::Matrix3d Cc = density * (C - vol * c * c.transpose());  // covariance about the centre of mass
  m.inertia = Cc.trace() * Eigen::Matrix3d::Identity() - Cc;
  return m;
}

MassProperties polygon_mass(const std::vector<std::vector<Eigen::Vector2d>>& loops, double density) {
  double A = 0, J = 0;
  Eigen::Vector2d S = Eigen::Vector2d::Zero();
  for (const auto& P : loops)
    for (std::size_t i = 0; i < P.size(); ++i) {
      const Eigen::Vector2d& p = P[i];
      const Eigen::Vector2d& q = P[(i + 1) % P.size()];
      const double cr = p.x() * q.y() - q.x() * p.y();
      A += cr / 2;
      S += cr / 6 * (p + q);  // first moments
      J += cr / 12 * (p.squaredNorm() + p.dot(q) + q.squaredNorm());  // polar second moment about 0
    }
  MassProperties m;
  m.mass = density * A;
  const Eigen::Vector2d c = S / A;
  m.com << c.x(), c.y(), 0;
  m.inertia(2, 2) = density * (J - A * c.squaredNorm());
  return m;
}

Eigen::Matrix3d inertia_about(const MassProperties& m, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = m.com - p;
  return m.inertia + m.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
}

}  // namespace varsph::bodies
