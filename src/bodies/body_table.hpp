#pragma once
// Rows of bodies.csv (one per rigid body per probe time) and moorings.csv (one per mooring): the state of
// each body after the step and the loads of that step (docs/results.md "bodies.csv").
#include <cmath>
#include <string>
#include <vector>

#include "bodies/rigid_bodies.hpp"
#include "io/csv_table.hpp"

namespace varsph::bodies {

inline const std::vector<std::string>& body_columns() {
  static const std::vector<std::string> c = {
      "time", "body", "x", "y", "z", "qw", "qx", "qy", "qz", "angle", "vx", "vy", "vz", "wx", "wy", "wz",
      "fluid_fx", "fluid_fy", "fluid_fz", "fluid_mx", "fluid_my", "fluid_mz",
      "contact_fx", "contact_fy", "contact_fz", "contact_mx", "contact_my", "contact_mz",
      "mooring_fx", "mooring_fy", "mooring_fz", "mooring_mx", "mooring_my", "mooring_mz"};
  return c;
}
inline const std::vector<std::string>& mooring_columns() {
  static const std::vector<std::string> c = {"time", "mooring", "body", "tension", "length"};
  return c;
}

// angle: rotation about z in 2D (counter-clockwise, radians); the rotation angle |theta| in 3D
template <int D>
std::vector<std::vector<std::string>> body_rows(const RigidBodies<D>& rb, double time) {
  using io::CsvTable;
  std::vector<std::vector<std::string>> rows;
  for (const auto& b : rb.bodies()) {
    std::vector<std::string> r = {CsvTable::num(time), CsvTable::num(long(b.scene_index))};
    auto add = [&](const Eigen::Vector3d& v) {
      for (int a = 0; a < 3; ++a) r.push_back(CsvTable::num(v[a]));
    };
    add(b.x);
    for (double c : {b.q.w(), b.q.x(), b.q.y(), b.q.z()}) r.push_back(CsvTable::num(c));
    const double angle = D == 2 ? 2 * std::atan2(b.q.z(), b.q.w())
                                : 2 * std::atan2(Eigen::Vector3d(b.q.x(), b.q.y(), b.q.z()).norm(), std::abs(b.q.w()));
    r.push_back(CsvTable::num(angle));
    add(b.v);
    add(b.w);
    add(b.loads.fluid_force);
    add(b.loads.fluid_torque);
    add(b.loads.contact_force);
    add(b.loads.contact_torque);
    add(b.loads.mooring_force);
    add(b.loads.mooring_torque);
    rows.push_back(std::move(r));
  }
  return rows;
}

template <int D>
std::vector<std::vector<std::string>> mooring_rows(const RigidBodies<D>& rb, double time) {
  using io::CsvTable;
  std::vector<std::vector<std::string>> rows;
  for (std::size_t k = 0; k < rb.moorings().size(); ++k) {
    const auto& m = rb.moorings()[k];
    rows.push_back({CsvTable::num(time), CsvTable::num(long(k)), CsvTable::num(long(m.spec.body)),
                    CsvTable::num(m.tension), CsvTable::num(m.length)});
  }
  return rows;
}

}  // namespace varsph::bodies
