#pragma once
// Mass, centre of mass and inertia tensor (about the centre of mass, world axes) of uniform solids.
// 2D bodies are per metre of depth: mass in kg/m, only inertia(2, 2) = Izz [kg m^2/m] is meaningful.
// Pure functions, tested against closed forms (tests/bodies/test_mass_properties.cpp).
#include <vector>

#include <Eigen/Core>

namespace varsph::bodies {

struct MassProperties {
  double mass = 0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about com
};

// Box [lo, hi] (2D: a rectangle, lo/hi z ignored).
MassProperties box_mass(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double density, int dim);
// Ball (3D, I = 2/5 M R^2) or disc (2D, Izz = M R^2 / 2).
MassProperties ball_mass(const Eigen::Vector3d& center, double radius, double density, int dim);
// Solid circular cylinder of the given axis (unit) and length, centred at `center` (3D); 2D: a disc.
MassProperties cylinder_mass(const Eigen::Vector3d& center, double radius, const Eigen::Vector3d& axis,
                             double length, double density, int dim);
// Closed triangle mesh (outward winding), exact by signed tetrahedra (Blow & Binstock 2004 / Tonon 2004):
// each face with the origin spans a tetrahedron whose covariance is det(A) A C A^T, C the canonical one.
MassProperties triangle_mesh_mass(const std::vector<Eigen::Vector3d>& vertices,
                                  const std::vector<Eigen::Vector3i>& faces, double density);
// Closed polygons in 2D (outer loops counter-clockwise, holes clockwise), by Green's theorem.
MassProperties polygon_mass(const std::vector<std::vector<Eigen::Vector2d>>& loops, double density);

// Inertia about a point p of a body with properties m (parallel-axis theorem, Steiner).
Eigen::Matrix3d inertia_about(const MassProperties& m, const Eigen::Vector3d& p);

}  // namespace varsph::bodies
