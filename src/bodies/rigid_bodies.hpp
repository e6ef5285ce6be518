#pragma once
// Rigid bodies moved by the fluid (scene bodies of kind "rigid"; docs/bodies.md). A body is state beside
// the particle store: mass properties, pose (quaternion; rotation about z in 2D), velocities, constraints,
// moorings and contact. Its particles stay boundary particles of the one store, tagged by `body`; each
// step this layer reduces the wall model's pair forces on them (Rates::boundary_reaction: the exact
// negative of what the fluid receives from them) to a force and torque, advances Newton-Euler, and writes
// their rigid positions, velocities, normals and accelerations back (ARCHITECTURE.md "Bodies").
//
// Determinism: per-particle loads are written into one slot per body particle, indexed by its place in
// the body (id - first id), and summed serially in that order: the same bits for any thread count, any
// cell order and (through an element-wise sum of the dense array, one non-zero term per slot) any number
// of MPI ranks.
#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "bodies/mass_properties.hpp"
#include "core/particle_store.hpp"
#include "physics/particle_view.hpp"
#include "physics/rates.hpp"
#include "scene/scene.hpp"
#include "sim/particle_fields.hpp"

namespace varsph {
template <int D>
class Simulation;
}

namespace varsph::bodies {

// Loads on a body over the last step, about its centre of mass [N, N m; 2D per metre].
struct BodyLoads {
  Eigen::Vector3d fluid_force = Eigen::Vector3d::Zero(), fluid_torque = Eigen::Vector3d::Zero();
  Eigen::Vector3d contact_force = Eigen::Vector3d::Zero(), contact_torque = Eigen::Vector3d::Zero();
  Eigen::Vector3d mooring_force = Eigen::Vector3d::Zero(), mooring_torque = Eigen::Vector3d::Zero();
};

struct RigidBody {
  int scene_index = -1;
  MassProperties mp;                    // at t = 0 (inertia about the centre of mass, world = body axes)
  bool pivoted = false;                 // hinge or fixed point: rotates about `pivot`
  bool hinge = false;                   // 3D hinge: rotates about `hinge_axis` only
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero(), hinge_axis = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d d0 = Eigen::Vector3d::Zero();  // centre of mass - pivot at t = 0
  Eigen::Matrix3d I0 = Eigen::Matrix3d::Zero();  // inertia about the rotation centre, body frame
  std::array<bool, 3> lock_t{}, lock_r{};
  std::int64_t first_id = 0;            // the body's particles have ids [first_id, first_id + count)
  std::size_t count = 0, offset = 0;    // offset of its slots in the dense load arrays
  // state (double precision whatever Real is)
  Eigen::Vector3d x = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
  Eigen::Vector3d L = Eigen::Vector3d::Zero();  // angular momentum about the rotation centre (world)
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d acc = Eigen::Vector3d::Zero(), alpha = Eigen::Vector3d::Zero();  // of the last step
  BodyLoads loads;
  // variational integrator: the fluid force and torque at the previous step's generalised midpoint (the
  // bodies' share of its a2, eq. 63); checkpointed with the state
  Eigen::Vector3d mid_force = Eigen::Vector3d::Zero(), mid_torque = Eigen::Vector3d::Zero();
  double radius = 0;                    // largest distance of its particles from the centre of mass
  Eigen::Vector3d center() const { return pivoted ? pivot : x; }
};

struct Mooring {
  scene::MooringSpec spec;
  int body = -1, anchor_body = -1;          // indices into RigidBodies::bodies()
  Eigen::Vector3d local = Eigen::Vector3d::Zero(), anchor_local = Eigen::Vector3d::Zero();  // body frames
  double rest = 0;
  double tension = 0, length = 0;           // last evaluation
};

template <int D>
class RigidBodies {
 public:
  // Registers the body-frame fields and sets every body up from the particles as built (ids = rows).
  RigidBodies(const scene::Scene& s, ParticleStore& store, ParticleFields<D>& f, double rho0, double c0);
  const std::vector<RigidBody>& bodies() const { return bodies_; }
  const std::vector<Mooring>& moorings() const { return moorings_; }
  // rigid-body index of scene body b, or -1
  int rigid_of(int scene_body) const {
    return scene_body >= 0 && std::size_t(scene_body) < of_scene_.size() ? of_scene_[std::size_t(scene_body)] : -1;
  }

  // Positions, velocities, normals (and accelerations for extrapolated walls) of the bodies' particles
  // in [0, n) from the body states.
  void place(ParticleFields<D>& f, std::size_t n, Field<Vec<D>>* acc) const;
  // One step of length dt for every body from the loads at the simulation's current state (call after
  // the fluid's forces of the step, before the drift's sort_and_bin places the particles). `drift`:
  // the velocity the positions move with, v_n + drift dt a (1: symplectic Euler / Verlet, 1/2: the
  // Taylor drift of DualSPHysics' Verlet). Every thread of a step region calls it.
  void advance(Simulation<D>& sim, double dt, double drift);
  // Loads at the current state without advancing (for outputs at t = 0 and tests).
  void evaluate_loads(Simulation<D>& sim);

  // The variational integrator (docs/bodies.md "The paper's variational integrator"). The fluid's update is
  // eq. (63), v_{k+1/2} = v_{k-1/2} + dt [(1 - alpha) a1 + alpha a2 + Gamma_k], with a1 at the new generalised
  // midpoint, a2 at the previous one and Gamma_k (repulsive walls) at q_k. The bodies are unknowns of the same
  // fixed point: each iterate places their particles at the midpoint (1 - alpha) x_k + alpha x_{k+1} of a
  // trial rigid step, and the reaction of a1 there gives the next trial. They take the exact reaction of
  // every term, so fluid and bodies exchange momentum to round-off:
  //   variational_begin(): once per step, at q_k: contact, moorings and (repulsive walls) the reaction of
  //     Gamma_k;
  //   midpoint_loads(): the reaction of `rates` at the midpoint `view` (R1; with `replace`, also R2: a2 rebuilt);
  //   variational_trial(): the rigid step from the state at q_k with F = (1 - alpha) R1 + alpha R2 + the loads
  //     at q_k + M g (the predictor: R2 for R1), and each body particle's chord velocity (x_{k+1} - x_k) / dt
  //     into v_out, the velocity its midpoint and the fixed point's residual are taken from;
  //   variational_accept(): the last trial becomes the state, R1 the next step's R2.
  void variational_begin(Simulation<D>& sim, bool gamma_at_qk);
  void midpoint_loads(Simulation<D>& sim, const physics::Rates<D>& rates, const physics::ParticleView<D>& view,
                      bool replace);
  void variational_trial(Simulation<D>& sim, double dt, double alpha, bool predictor, Vec<D>* v_out);
  void variational_accept(Simulation<D>& sim, double dt);
  // True for the particles of a rigid body (by their scene body index).
  bool is_rigid(std::int32_t scene_body) const { return rigid_of(scene_body) >= 0; }

  // Total linear and angular momentum (about the origin) of the bodies [kg m/s, kg m^2/s].
  Eigen::Vector3d momentum() const;
  Eigen::Vector3d angular_momentum() const;
  double kinetic_energy() const;
  double potential_energy(const Eigen::Vector3d& g) const;  // - M g . x

  // Wall seconds spent in advance() since the start (benchmarks: the coupling's share of a step).
  double seconds() const { return seconds_; }

  nlohmann::json save_state() const;
  void restore_state(const nlohmann::json& j);

 private:
  void reduce_loads(Simulation<D>& sim);
  // the reaction of `rates` at `view` (fluid part; contact and moorings at the current state when
  // `contact`) into b.loads, summed in body order
  void reduce_loads(Simulation<D>& sim, const physics::Rates<D>* rates, const physics::ParticleView<D>& view,
                    bool contact);
  void step_body(RigidBody& b, const Eigen::Vector3d& F, const Eigen::Vector3d& T, double dt, double drift) const;
  void mooring_loads();
  void check_start(const scene::Scene& s, const ParticleFields<D>& f, std::size_t n);
  void check_in_domain(const RigidBody& b, double t) const;
  double lo_[D] = {}, hi_[D] = {};
  bool periodic_[D] = {};
  std::vector<RigidBody> bodies_;
  std::vector<Mooring> moorings_;
  std::vector<int> of_scene_;
  std::vector<std::uint8_t> rigid_scene_;     // per scene body: 1 when rigid (the reaction pass's filter)
  Field<Vec<D>>* local_ = nullptr;            // body-frame offset from the centre of mass at t = 0
  Field<Vec<D>>* local_normal_ = nullptr;     // body-frame normal
  std::vector<Vec<D>> react_, contact_f_;     // per particle (sized once, grown with the store)
  std::vector<Eigen::Vector3d> r1_force_, r1_torque_;  // per body: the new midpoint's reaction (variational)
  std::vector<BodyLoads> at_qk_;                       // per body: contact, moorings, Gamma_k at q_k (variational)
  std::vector<RigidBody> trial_;                       // per body: the fixed point's trial state at t_{k+1}
  std::vector<Eigen::Vector3d> chord_x_;               // per body: (X_{k+1} - X_k) / dt of the trial
  std::vector<Eigen::Matrix3d> chord_r_;               // per body: (R_{k+1} - R_k) / dt of the trial
  mutable std::vector<Eigen::Matrix3d> rot_;  // per body, refreshed by place()
  std::vector<double> dense_;                 // 12 per body particle: fluid f, r x f, contact f, r x f
  scene::ContactSpec contact_;
  double contact_k_ = 0, contact_gamma_ = 0, contact_d_ = 0;
  int dim_ = D;
  double seconds_ = 0;
  std::chrono::steady_clock::time_point started_;
};

}  // namespace varsph::bodies
