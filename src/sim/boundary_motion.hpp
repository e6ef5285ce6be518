#pragma once
// Prescribed motion of boundary bodies (a sloshing tank, a moving lid, a paddle): positions and
// velocities of their particles are set from the motion law at a given time; the velocity is what the
// wall models see (continuity and viscosity use v_i - v_j). Laws (x0: reference position at t = 0):
//   translation  x = x0 + u t                                  v = u
//   rotation     x = c + R(omega t) (x0 - c)                   v = omega x (x - c)
//   oscillation  x = x0 + A [sin(2 pi f t + phi) - sin(phi)]   v = 2 pi f A cos(2 pi f t + phi)
// and the accelerations a = 0, omega x (omega x (x - c)), -(2 pi f)^2 A sin(2 pi f t + phi).
// Each law acts for start <= t <= end (before: at rest at x0; after: frozen where it stopped).
#include <vector>

#include <nlohmann/json.hpp>

#include "core/particle_store.hpp"
#include "core/real.hpp"

namespace varsph {

template <int D>
struct MotionLaw {
  enum class Type { None, Translation, Rotation, Oscillation } type = Type::None;
  Vec<D> velocity = Vec<D>::Zero();   // translation [m/s]
  Vec<D> center = Vec<D>::Zero();     // rotation centre [m]
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();  // rotation rate [rad/s] (2D: z component)
  Vec<D> amplitude = Vec<D>::Zero();  // oscillation [m]
  double frequency = 0, phase = 0;    // [Hz], [rad]
  double start = 0, end = 1e300;      // [s]
};

// Parses `bodies.N.motion` (InputError naming the key). Returns Type::None when absent.
template <int D>
MotionLaw<D> parse_motion(const nlohmann::json& motion, const std::string& where);

template <int D>
class BoundaryMotion {
 public:
  // Registers reference positions/normals only when some body moves (nothing otherwise).
  BoundaryMotion(std::vector<MotionLaw<D>> laws, ParticleStore& store);
  bool active() const { return active_; }
  // Sets x, v (and normals, and the accelerations when `acc` is given) of the moving bodies' particles
  // to the law at time t.
  void apply(double t, Field<Vec<D>>& x, Field<Vec<D>>& v, Field<Vec<D>>& normal,
             const Field<std::int32_t>& body, Field<Vec<D>>* acc = nullptr) const;
  // Acceleration of a particle of law k at position x and time t (zero outside [start, end]).
  Vec<D> acceleration(const MotionLaw<D>& law, double t, const Vec<D>& x) const;
  // Records the current positions/normals as references (after the particles are built).
  void capture_reference(const Field<Vec<D>>& x, const Field<Vec<D>>& normal);
  // Position, velocity and rotation of law k at time t for a reference point x0.
  void evaluate(const MotionLaw<D>& law, double t, const Vec<D>& x0, Vec<D>& x, Vec<D>& v,
                Eigen::Matrix<Real, D, D>& R) const;

 private:
  std::vector<MotionLaw<D>> laws_;
  bool active_ = false;
  Field<Vec<D>>* x0_ = nullptr;
  Field<Vec<D>>* n0_ = nullptr;
};

}  // namespace varsph
