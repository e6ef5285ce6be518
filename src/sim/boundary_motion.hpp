#pragma once
// Prescribed motion of boundary bodies (a sloshing tank, a moving lid, a paddle): positions and
// velocities of their particles are set from the motion law at a given time; the velocity is what the
// wall models see (continuity and viscosity use v_i - v_j). Laws (x0: reference position at t = 0):
//   translation  x = x0 + u t                                  v = u
//   rotation     x = c + R(omega t) (x0 - c)                   v = omega x (x - c)
//   oscillation  x = x0 + A [sin(2 pi f t + phi) - sin(phi)]   v = 2 pi f A cos(2 pi f t + phi)
// and the accelerations a = 0, omega x (omega x (x - c)), -(2 pi f)^2 A sin(2 pi f t + phi).
// Wavemakers (docs/waves.md), X(t) the paddle signal at the still-water level (waves/paddle_signal.hpp), waves
// travelling towards +x, vertical axis y (2D) or z (3D):
//   piston       x = x0 + X e_x                             v = X' e_x            a = X'' e_x
//   flap         x = c + R(phi) (x0 - c), c the hinge, theta = atan(X / (h - l)) (or the file's angle),
//                phi = -theta about z (2D) / +theta about y (3D): the top moves towards +x for X > 0;
//                v = phi' e x r,  a = phi'' e x r + phi' e x (phi' e x r)  (r = x - c)
// Each law acts for start <= t <= end (before: at rest at x0; after: frozen where it stopped).
// Active absorption at a piston or a flap (AWAS, `motion.awas`; docs/waves.md "Active absorption"): the paddle's signal X(t)
// gets a correction X_c whose velocity is U_c = G (eta_T - eta_M) - X_c / T_d (Altomare et al. 2017, Coastal Eng.
// 127, eq. 12, after Schaffer & Klopman 2000: G = sqrt(g/h) in the shallow-water form, omega / (H/S) in the linear
// one; T_d the optional drift time), eta_T the linear-theory target and eta_M the elevation measured at a gauge a
// distance `gauge` in front of the paddle's face. U_c is set once per step from the state at its start and held
// over the step: X_c(t) = X_c(t_k) + (t - t_k) U_c, so the motion stays a function of t and of the correction's
// state (t_k, X_c(t_k), U_c, the still-water reading), which checkpoints carry (save_state / restore_state).
// A flap (hinged at the bed or below it) takes X + X_c as its displacement at the still-water level, theta =
// atan((X + X_c) / (h - l)); its shallow gain is sqrt(g/h) (h - l) / (h/2 - l), matching its depth-averaged velocity.
#include <functional>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/particle_store.hpp"
#include "core/real.hpp"
#include "waves/paddle_signal.hpp"

namespace varsph {
namespace scene {
struct Scene;
}

template <int D>
struct MotionLaw {
  enum class Type { None, Translation, Rotation, Oscillation, Piston, Flap } type = Type::None;
  Vec<D> velocity = Vec<D>::Zero();   // translation [m/s]
  Vec<D> center = Vec<D>::Zero();     // rotation centre [m]
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();  // rotation rate [rad/s] (2D: z component)
  Vec<D> amplitude = Vec<D>::Zero();  // oscillation [m]
  double frequency = 0, phase = 0;    // [Hz], [rad]
  double start = 0, end = 1e300;      // [s]
  // wavemakers: the paddle signal X(t) at the still-water level [m] (or the flap's angle [rad] when
  // paddle_angle), the flap's hinge (in `center`) and its arm h - l [m]
  std::shared_ptr<const waves::PaddleSignal> paddle;
  bool paddle_angle = false;
  double arm = 0;
  // active absorption (a piston, or a flap hinged at the bed or below it; `motion.awas`)
  struct Absorption {
    bool on = false;
    double gain = 0;        // G [1/s]: sqrt(g/h) ("shallow") or omega/(H/S) at the (peak) period ("linear")
    double start = 0;       // [s] absolute time from which the correction acts (default: the ramp's end)
    double gauge = 0;       // distance of the gauge from the paddle's face [m]
    double face = 0;        // the face's x at rest [m]
    double across = 0;      // 3D: the gauge line's y [m]
    double bed = 0, depth = 0;
    double drift_time = 0;  // T_d [s]; 0: no drift correction
    double ramp = 0;        // the signal's ramp [s] (the target is ramped alike)
    std::vector<waves::Component> target;  // eta_T = r(tau) sum_i a_i cos(omega_i tau + phase_i - k_i x)
    std::vector<double> k;                 // k_i [1/m]
  } awas;
};

// The state of one law's absorption (per law; checkpointed).
struct AbsorptionState {
  double t_ref = 0;     // time of the last update [s]
  double shift = 0;     // X_c(t_ref) [m]
  double u = 0;         // U_c over the current step [m/s]
  double level0 = 0;    // the gauge's still-water reading [m] (taken at the first update)
  bool have_level0 = false;
  double eta_target = 0, eta_measured = 0;  // at the last update [m]
};

// Parses `bodies.N.motion` (InputError naming the key). Returns Type::None when absent. Wavemakers need the
// scene (the fluid's depth, the domain, gravity, the scene's folder for a paddle file) and the body's index.
template <int D>
MotionLaw<D> parse_motion(const nlohmann::json& motion, const std::string& where, const scene::Scene* scene = nullptr,
                          std::size_t body = 0);

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
  // Records the current positions/normals as references (after the particles are built).
  void capture_reference(const Field<Vec<D>>& x, const Field<Vec<D>>& normal);
  const std::vector<MotionLaw<D>>& laws() const { return laws_; }
  // Whether some law absorbs actively (motion.awas).
  bool absorbing() const { return absorbing_; }
  // Updates every absorbing law's correction at time t from the free-surface level that `level(x, y)` reads on
  // the vertical line at horizontal position x (3D: across position y). Call once at the start of each step,
  // outside parallel regions, on the state at t (before the walls move for the step).
  void absorb(double t, const std::function<double(double, double)>& level);
  const std::vector<AbsorptionState>& absorption() const { return awas_; }
  nlohmann::json save_state() const;
  void restore_state(const nlohmann::json& j);

 private:
  // Position, velocity and rotation of a law at time t for a reference point x0; `paddle` is the law's
  // wavemaker state at t (evaluated once per law and call, not per particle).
  void evaluate(const MotionLaw<D>& law, const waves::PaddleState& paddle, double t, const Vec<D>& x0, Vec<D>& x,
                Vec<D>& v, Eigen::Matrix<Real, D, D>& R) const;
  // Acceleration of a particle of a law at position x and time t (zero outside [start, end]).
  Vec<D> acceleration(const MotionLaw<D>& law, const waves::PaddleState& paddle, double t, const Vec<D>& x) const;
  // The paddle's angle state (theta, theta', theta'') of a flap, or its displacement state of a piston.
  // With an absorption state `c`, X(t) carries its correction (X + X_c, X' + U_c) before a flap's angle is taken.
  waves::PaddleState paddle_state(const MotionLaw<D>& law, double t, const AbsorptionState* c = nullptr) const;

  std::vector<MotionLaw<D>> laws_;
  mutable std::vector<waves::PaddleState> paddle_;  // per law, at the time of the last apply()
  std::vector<AbsorptionState> awas_;                // per law
  bool active_ = false, absorbing_ = false;
  Field<Vec<D>>* x0_ = nullptr;
  Field<Vec<D>>* n0_ = nullptr;
};

}  // namespace varsph
