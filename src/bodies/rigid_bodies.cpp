#include "bodies/rigid_bodies.hpp"

#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "bodies/contact.hpp"
#include "core/errors.hpp"
#include "core/team.hpp"
#include "neighbors/neighbor_grid.hpp"
#include "parallel/communicator.hpp"
#include "physics/pair_loop.hpp"
#include "sim/mesh_bodies.hpp"
#include "sim/simulation.hpp"

namespace varsph::bodies {
namespace {

Eigen::Vector3d v3(const std::vector<double>& v) {
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (std::size_t a = 0; a < v.size() && a < 3; ++a) r[Eigen::Index(a)] = v[a];
  return r;
}
template <int D>
Eigen::Vector3d v3(const Vec<D>& v) {
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (int a = 0; a < D; ++a) r[a] = double(v[a]);
  return r;
}
template <int D>
Vec<D> vd(const Eigen::Vector3d& v) {
  Vec<D> r;
  for (int a = 0; a < D; ++a) r[a] = Real(v[a]);
  return r;
}

// Uniform-solid mass properties of a scene body's shape at unit density (scaled by the caller).
template <int D>
MassProperties shape_mass(const scene::Scene& s, std::size_t index) {
  const scene::BodySpec& b = s.bodies[index];
  if (b.shape == "box") return box_mass(v3(b.min), v3(b.max), 1.0, D);
  if (b.shape == "sphere") return ball_mass(v3(b.center), b.radius, 1.0, D);
  if (b.shape == "cylinder") return cylinder_mass(v3(b.center), b.radius, v3(b.rigid.cylinder_axis), b.rigid.cylinder_length, 1.0, D);
  return mesh_mass_properties<D>(s, index);  // the geometry module (closed meshes only)
}

// Exponential map: the rotation by the vector phi (angle |phi| about phi / |phi|) as a unit quaternion.
Eigen::Quaterniond rotation_of(const Eigen::Vector3d& phi) {
  const double a = phi.norm();
  if (a < 1e-300) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, phi / a));
}

}  // namespace

template <int D>
RigidBodies<D>::RigidBodies(const scene::Scene& s, ParticleStore& store, ParticleFields<D>& f, double rho0, double c0)
    : contact_(s.contact) {
  of_scene_.assign(s.bodies.size(), -1);
  rigid_scene_.assign(s.bodies.size(), 0);
  local_ = &store.add<Vec<D>>("rigid_local", {.exported = false});
  local_normal_ = &store.add<Vec<D>>("rigid_local_normal", {.exported = false});
  const std::size_t n = store.size();
  for (std::size_t i = 0; i < n; ++i) {  // zero where no body writes (a resize leaves Eigen vectors unset)
    (*local_)[i].setZero();
    (*local_normal_)[i].setZero();
  }
  for (std::size_t bi = 0; bi < s.bodies.size(); ++bi) {
    const scene::BodySpec& spec = s.bodies[bi];
    if (spec.kind != "rigid") continue;
    const std::string where = s.file.string() + ": bodies." + std::to_string(bi);
    RigidBody b;
    b.scene_index = int(bi);
    const scene::RigidSpec& r = spec.rigid;
    // mass properties: the uniform solid, or what the scene gives (the shape's where it gives nothing)
    const bool given_all = r.mass > 0 && !r.center_of_mass.empty() && !r.inertia.empty();
    MassProperties unit = given_all ? MassProperties{} : shape_mass<D>(s, bi);
    if (!given_all && !(unit.mass > 0))
      throw InputError(where + ": the body's volume is not positive (" + std::to_string(unit.mass) +
                       "); is the mesh closed and oriented outward?");
    if (r.density > 0) {
      b.mp = unit;
      b.mp.mass *= r.density;
      b.mp.inertia *= r.density;
    } else {
      b.mp.mass = r.mass;
      b.mp.com = r.center_of_mass.empty() ? unit.com : v3(r.center_of_mass);
      if (!r.inertia.empty()) {
        if (D == 2) b.mp.inertia(2, 2) = r.inertia[0];
        else
          b.mp.inertia << r.inertia[0], r.inertia[3], r.inertia[4], r.inertia[3], r.inertia[1], r.inertia[5],
              r.inertia[4], r.inertia[5], r.inertia[2];
      } else {
        // the uniform solid's inertia about its own centroid, moved to the given centre of mass
        MassProperties m = unit;
        m.inertia *= r.mass / unit.mass;
        m.mass = r.mass;
        b.mp.inertia = inertia_about(m, b.mp.com);
      }
    }
    if (D == 2) b.mp.com.z() = 0;
    b.x = b.mp.com;
    b.v = v3(spec.velocity);
    if (D == 2) b.w = Eigen::Vector3d(0, 0, r.angular_velocity[0]);
    else b.w = v3(r.angular_velocity);
    for (int a = 0; a < D; ++a) b.lock_t[std::size_t(a)] = r.lock_translation[std::size_t(a)];
    if (D == 2) b.lock_r = {true, true, bool(r.lock_rotation[0])};
    else for (int a = 0; a < 3; ++a) b.lock_r[std::size_t(a)] = r.lock_rotation[std::size_t(a)];
    b.pivoted = r.constraint != "free";
    if (b.pivoted) {
      b.pivot = v3(r.pivot);
      b.d0 = b.x - b.pivot;
      b.hinge = r.constraint == "hinge";
      if (b.hinge) b.hinge_axis = v3(r.axis).normalized();
      b.v = b.w.cross(b.d0);  // a pivoted body moves with its rotation only
    }
    b.I0 = b.pivoted ? inertia_about(b.mp, b.pivot) : b.mp.inertia;
    b.L = b.I0 * b.w;
    // its particles: ids are the build rows here, one contiguous range per body
    bool found = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (f.body[i] != std::int32_t(bi)) continue;
      if (!found) b.first_id = f.id[i];
      found = true;
      ++b.count;
      (*local_)[i] = vd<D>(v3<D>(f.x[i]) - b.x);
      (*local_normal_)[i] = f.normal[i];
    }
    b.offset = bodies_.empty() ? 0 : bodies_.back().offset + bodies_.back().count;
    of_scene_[bi] = int(bodies_.size());
    rigid_scene_[bi] = 1;
    bodies_.push_back(b);
  }
  // moorings: attachment points in the bodies' frames at t = 0
  for (const auto& ms : s.moorings) {
    Mooring m;
    m.spec = ms;
    m.body = of_scene_[std::size_t(ms.body)];
    m.local = v3(ms.point) - bodies_[std::size_t(m.body)].x;
    if (ms.anchor_body >= 0) {
      m.anchor_body = of_scene_[std::size_t(ms.anchor_body)];
      m.anchor_local = v3(ms.anchor) - bodies_[std::size_t(m.anchor_body)].x;
    } else {
      m.anchor_local = v3(ms.anchor);
    }
    m.rest = ms.rest_length >= 0 ? ms.rest_length : (v3(ms.point) - v3(ms.anchor)).norm();
    moorings_.push_back(m);
  }
  // contact (bodies/contact.hpp): the fluid's stiffness over one particle face and one spacing
  const double dx = s.spacing;
  contact_d_ = contact_.distance * dx;
  contact_k_ = contact_.stiffness > 0 ? contact_.stiffness : rho0 * c0 * c0 * std::pow(dx, D - 2);
  const double m = rho0 * std::pow(dx, D), le = std::log(contact_.restitution);
  const double zeta = contact_.restitution >= 1 ? 0.0 : -le / std::sqrt(std::numbers::pi * std::numbers::pi + le * le);
  contact_gamma_ = 2 * zeta * std::sqrt(m * contact_k_);
  check_start(s, f, n);
  for (int a = 0; a < D; ++a) {
    lo_[a] = s.domain_min[std::size_t(a)];
    hi_[a] = s.domain_max[std::size_t(a)];
    periodic_[a] = s.periodic[std::size_t(a)];
  }
  std::size_t total = 0;
  for (const auto& b : bodies_) total += b.count;
  dense_.assign(12 * total, 0.0);
  rot_.assign(bodies_.size(), Eigen::Matrix3d::Identity());
  // the variational integrator's per-body scratch, sized once (the body count never changes)
  r1_force_.assign(bodies_.size(), Eigen::Vector3d::Zero());
  r1_torque_.assign(bodies_.size(), Eigen::Vector3d::Zero());
  at_qk_.assign(bodies_.size(), BodyLoads{});
  trial_ = bodies_;
  chord_x_.assign(bodies_.size(), Eigen::Vector3d::Zero());
  chord_r_.assign(bodies_.size(), Eigen::Matrix3d::Zero());
}

template <int D>
void RigidBodies<D>::check_start(const scene::Scene& s, const ParticleFields<D>& f, std::size_t n) {
  // the extent of each body about its centre (the domain check of advance())
  for (std::size_t i = 0; i < n; ++i) {
    const int k = rigid_of(f.body[i]);
    if (k >= 0) bodies_[std::size_t(k)].radius = std::max(bodies_[std::size_t(k)].radius, double((*local_)[i].norm()));
  }
  // bodies that start overlapping each other or a wall: boundary particles of two bodies closer than
  // half a spacing (touching bodies sit one spacing apart, as lattice rows do)
  const double d = 0.5 * s.spacing;
  NeighborGrid<D> grid;
  typename NeighborGrid<D>::Options o;
  o.hashed = true;
  o.cell_size = Real(d);
  grid.configure(o);
  std::vector<Vec<D>> x(f.x.data.begin(), f.x.data.begin() + long(n));
  std::vector<std::uint32_t> perm;
  grid.build(x, perm);
  for (const auto& blk : grid.blocks())
    for (std::uint32_t i = blk.begin; i < blk.end; ++i) {
      const std::uint32_t pi = perm[i];
      if (f.kind[pi] == 0 || rigid_of(f.body[pi]) < 0) continue;
      for (std::uint32_t r = blk.nbr_begin; r < blk.nbr_end; ++r)
        for (std::uint32_t j = grid.ranges()[r].begin; j < grid.ranges()[r].end; ++j) {
          const std::uint32_t pj = perm[j];
          if (f.kind[pj] == 0 || f.body[pj] == f.body[pi]) continue;
          if (double((f.x[pi] - f.x[pj]).norm()) < d)
            throw InputError(s.file.string() + ": bodies." + std::to_string(f.body[pi]) + ": the rigid body starts "
                             "overlapping bodies." + std::to_string(f.body[pj]) + " (particles " +
                             std::to_string(double((f.x[pi] - f.x[pj]).norm())) + " m apart at (" +
                             std::to_string(double(f.x[pi][0])) + ", " + std::to_string(double(f.x[pi][1])) +
                             "); expected at least half a spacing): move it clear");
        }
    }
  // a fixed mooring anchor inside a body would pull it into itself: a point inside a filled lattice is
  // within sqrt(d)/2 spacings of one of its particles (0.9 dx: also refuses 0.4 dx outside the surface)
  for (std::size_t k = 0; k < s.moorings.size(); ++k) {
    if (s.moorings[k].anchor_body >= 0) continue;
    const Eigen::Vector3d a = v3(s.moorings[k].anchor);
    for (std::size_t i = 0; i < n; ++i)
      if (rigid_of(f.body[i]) >= 0 && (v3<D>(f.x[i]) - a).norm() < 0.9 * s.spacing)
        throw InputError(s.file.string() + ": moorings." + std::to_string(k) + ".anchor: lies inside bodies." +
                         std::to_string(f.body[i]) + "; expected a fixed point outside every rigid body");
  }
}

template <int D>
void RigidBodies<D>::check_in_domain(const RigidBody& b, double t) const {
  for (int a = 0; a < D; ++a) {
    if (periodic_[a]) continue;
    if (b.x[a] - b.radius < lo_[a] || b.x[a] + b.radius > hi_[a] || !std::isfinite(b.x[a]))
      throw NumericalError("rigid body bodies." + std::to_string(b.scene_index) + " left the domain at t = " +
                           std::to_string(t) + " s (centre " + std::to_string(b.x[a]) + " m on axis " +
                           std::to_string(a) + ", domain [" + std::to_string(lo_[a]) + ", " + std::to_string(hi_[a]) +
                           "]): enlarge domain.min/max, or constrain or moor the body");
  }
}

template <int D>
void RigidBodies<D>::place(ParticleFields<D>& f, std::size_t n, Field<Vec<D>>* acc) const {
  // rotation matrices of every body, then each particle from its body-frame offset
  team_single([&] {
    for (std::size_t k = 0; k < bodies_.size(); ++k) rot_[k] = bodies_[k].q.toRotationMatrix();
  });
  for_each_particle(n, [&](std::size_t i) {
    const int k = rigid_of(f.body[i]);
    if (k < 0 || f.kind[i] == 0) return;
    const RigidBody& b = bodies_[std::size_t(k)];
    const Eigen::Matrix3d& R = rot_[std::size_t(k)];
    const Eigen::Vector3d r = R * v3<D>((*local_)[i]);
    f.x[i] = vd<D>(b.x + r);
    f.v[i] = vd<D>(b.v + b.w.cross(r));
    f.normal[i] = vd<D>(R * v3<D>((*local_normal_)[i]));
    if (acc) (*acc)[i] = vd<D>(b.acc + b.alpha.cross(r) + b.w.cross(b.w.cross(r)));
  });
}

template <int D>
void RigidBodies<D>::reduce_loads(Simulation<D>& sim) {
  reduce_loads(sim, &sim.rates(), sim.current_view(), true);
}

template <int D>
void RigidBodies<D>::reduce_loads(Simulation<D>& sim, const physics::Rates<D>* rates,
                                  const physics::ParticleView<D>& view, bool contact) {
  auto& f = sim.fields();
  const std::size_t stored = sim.store().size(), n = sim.size();
  team_single([&] {
    if (react_.size() < stored) {  // grows with the store only (no allocation in a steady run)
      react_.resize(stored);
      contact_f_.resize(stored);
    }
  });
  const physics::BoundaryFilter only{f.body.data.data(), rigid_scene_.data(), std::int32_t(rigid_scene_.size())};
  const bool fluid = rates != nullptr;
  if (fluid) rates->boundary_reaction(sim.grid(), view, react_.data(), only);
  const bool contact_on = contact && contact_.enabled;
  if (contact_on) {
    ContactPass<D> pass{f.x.data.data(), f.v.data.data(), f.kind.data.data(), f.body.data.data(), only,
                        Real(contact_d_ * contact_d_), Real(contact_d_), Real(contact_k_), Real(contact_gamma_),
                        contact_f_.data()};
    for_each_particle_pairs<D>(sim.grid(), std::span<const Vec<D>>(f.x.data), sim.rates().support(), pass);
  }
  // one slot per body particle, in body order: (f, r x f) of the fluid and of contact
  team_single([&] { std::fill(dense_.begin(), dense_.end(), 0.0); });
  double* dense = dense_.data();
  for_each_particle(n, [&](std::size_t i) {
    const int k = rigid_of(f.body[i]);
    if (k < 0 || f.kind[i] == 0) return;
    const RigidBody& b = bodies_[std::size_t(k)];
    double* slot = dense + 12 * (b.offset + std::size_t(f.id[i] - b.first_id));
    // the offset from the body's frame, not x_i - x (a periodic axis may have wrapped x_i)
    const Eigen::Vector3d r = rot_[std::size_t(k)] * v3<D>((*local_)[i]);
    const Eigen::Vector3d ff = fluid ? v3<D>(react_[i]) : Eigen::Vector3d::Zero(), tf = r.cross(ff);
    const Eigen::Vector3d fc = contact_on ? v3<D>(contact_f_[i]) : Eigen::Vector3d::Zero(), tc = r.cross(fc);
    for (int a = 0; a < 3; ++a) {
      slot[a] = ff[a];
      slot[3 + a] = tf[a];
      slot[6 + a] = fc[a];
      slot[9 + a] = tc[a];
    }
  });
  team_single([&] {
    // distributed: every slot is written by the one rank owning that particle; the element-wise sum adds
    // zeros to it, so every rank holds the serial values and sums them in the same order
    if (sim.distributed()) sim.comm().sum(std::span<double>(dense_));
    for (auto& b : bodies_) {
      BodyLoads l;
      const double* s = dense + 12 * b.offset;
      for (std::size_t k = 0; k < b.count; ++k, s += 12) {
        l.fluid_force += Eigen::Vector3d(s[0], s[1], s[2]);
        l.fluid_torque += Eigen::Vector3d(s[3], s[4], s[5]);
        l.contact_force += Eigen::Vector3d(s[6], s[7], s[8]);
        l.contact_torque += Eigen::Vector3d(s[9], s[10], s[11]);
      }
      b.loads = l;
    }
    if (contact) mooring_loads();
  });
}

template <int D>
void RigidBodies<D>::mooring_loads() {
  for (auto& m : moorings_) {
    RigidBody& b = bodies_[std::size_t(m.body)];
    const Eigen::Vector3d rb = b.q * m.local;
    const Eigen::Vector3d p = b.x + rb, vp = b.v + b.w.cross(rb);
    Eigen::Vector3d a = m.anchor_local, va = Eigen::Vector3d::Zero(), ra = Eigen::Vector3d::Zero();
    if (m.anchor_body >= 0) {
      const RigidBody& o = bodies_[std::size_t(m.anchor_body)];
      ra = o.q * m.anchor_local;
      a = o.x + ra;
      va = o.v + o.w.cross(ra);
    }
    const Eigen::Vector3d l = a - p;
    m.length = l.norm();
    const Eigen::Vector3d u = m.length > 0 ? Eigen::Vector3d(l / m.length) : Eigen::Vector3d::Zero();
    // linear spring-damper along the line: T = k (len - L0) + c d(len)/dt; a slack line pushes nothing
    double T = m.spec.stiffness * (m.length - m.rest) + m.spec.damping * (va - vp).dot(u);
    if (m.spec.slack && (m.length < m.rest || T < 0)) T = 0;
    m.tension = T;
    const Eigen::Vector3d F = T * u;  // on the body, towards the anchor
    b.loads.mooring_force += F;
    b.loads.mooring_torque += rb.cross(F);
    if (m.anchor_body >= 0) {
      RigidBody& o = bodies_[std::size_t(m.anchor_body)];
      o.loads.mooring_force -= F;
      o.loads.mooring_torque += ra.cross(Eigen::Vector3d(-F));
    }
  }
}

template <int D>
void RigidBodies<D>::step_body(RigidBody& b, const Eigen::Vector3d& F, const Eigen::Vector3d& Tc, double dt,
                               double drift) const {
  const Eigen::Vector3d v_old = b.v, w_old = b.w;
  const Eigen::Matrix3d R = b.q.toRotationMatrix();
  // torque about the rotation centre: about the centre of mass plus (com - centre) x F
  const Eigen::Vector3d T = b.pivoted ? Eigen::Vector3d(Tc + (b.x - b.pivot).cross(F)) : Tc;
  // --- rotation (Newton-Euler about the centre of mass, or about the pivot) ---
  Eigen::Vector3d w_drift;
  if (D == 2) {
    const double Izz = b.I0(2, 2);
    const double al = b.lock_r[2] ? 0.0 : T.z() / Izz;
    const double wn = b.lock_r[2] ? 0.0 : b.w.z();
    b.w = Eigen::Vector3d(0, 0, wn + dt * al);
    w_drift = Eigen::Vector3d(0, 0, wn + drift * dt * al);
    b.L = Izz * b.w;
  } else {
    const bool any_lock = b.lock_r[0] || b.lock_r[1] || b.lock_r[2];
    const Eigen::Matrix3d Iw = R * b.I0 * R.transpose();
    if (!any_lock && !b.hinge) {
      // the angular momentum is the state (exact conservation without torque); omega = I(q)^-1 L
      const Eigen::Vector3d L_drift = b.L + drift * dt * T;
      b.L += dt * T;
      w_drift = Iw.ldlt().solve(L_drift);
    } else {
      // Euler's equations restricted to the free directions: I a = T - w x I w
      const Eigen::Vector3d rhs = T - b.w.cross(Iw * b.w);
      Eigen::Vector3d al = Eigen::Vector3d::Zero();
      if (b.hinge) {
        const Eigen::Vector3d& e = b.hinge_axis;
        al = e * (e.dot(T) / e.dot(Iw * e));  // rotation about the fixed axis only
      } else {
        // the free rows and columns of I, the locked ones replaced by the identity (their al stays 0)
        Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
        Eigen::Vector3d y = Eigen::Vector3d::Zero();
        for (int i = 0; i < 3; ++i) {
          if (b.lock_r[std::size_t(i)]) continue;
          y[i] = rhs[i];
          for (int j = 0; j < 3; ++j)
            if (!b.lock_r[std::size_t(j)]) A(i, j) = Iw(i, j);
        }
        al = A.ldlt().solve(y);
        for (int a = 0; a < 3; ++a)
          if (b.lock_r[std::size_t(a)]) al[a] = 0;
      }
      Eigen::Vector3d wn = b.w;
      for (int a = 0; a < 3; ++a)
        if (b.lock_r[std::size_t(a)]) wn[a] = 0;
      if (b.hinge) wn = b.hinge_axis * b.hinge_axis.dot(wn);
      w_drift = wn + drift * dt * al;
      b.w = wn + dt * al;
    }
  }
  b.q = (rotation_of(dt * w_drift) * b.q).normalized();
  if (D == 3 && !(b.lock_r[0] || b.lock_r[1] || b.lock_r[2] || b.hinge)) {
    const Eigen::Matrix3d R1 = b.q.toRotationMatrix();
    b.w = (R1 * b.I0 * R1.transpose()).ldlt().solve(b.L);
  } else if (D == 3) {
    const Eigen::Matrix3d R1 = b.q.toRotationMatrix();
    b.L = R1 * b.I0 * R1.transpose() * b.w;
  }
  // --- translation ---
  if (b.pivoted) {
    const Eigen::Vector3d d = b.q * b.d0;  // the centre of mass rides on the rotation about the pivot
    b.x = b.pivot + d;
    b.v = b.w.cross(d);
  } else {
    Eigen::Vector3d a = F / b.mp.mass;
    Eigen::Vector3d vn = b.v;
    for (int k = 0; k < 3; ++k)
      if (b.lock_t[std::size_t(k)] || k >= D) {
        a[k] = 0;
        vn[k] = 0;
      }
    b.x += dt * (vn + drift * dt * a);
    b.v = vn + dt * a;
  }
  b.acc = (b.v - v_old) / dt;
  b.alpha = (b.w - w_old) / dt;
}

template <int D>
void RigidBodies<D>::evaluate_loads(Simulation<D>& sim) {
  reduce_loads(sim);
}

template <int D>
void RigidBodies<D>::variational_begin(Simulation<D>& sim, bool gamma_at_qk) {
  team_single([&] { started_ = std::chrono::steady_clock::now(); });
  // contact and moorings at q_k, with the reaction of Gamma_k (eq. 58 at q_k) when the walls are repulsive
  reduce_loads(sim, gamma_at_qk ? &sim.rates() : nullptr, sim.current_view(), true);
  team_single([&] {
    for (std::size_t k = 0; k < bodies_.size(); ++k) at_qk_[k] = bodies_[k].loads;
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  });
}

template <int D>
void RigidBodies<D>::midpoint_loads(Simulation<D>& sim, const physics::Rates<D>& rates,
                                    const physics::ParticleView<D>& view, bool replace) {
  team_single([&] { started_ = std::chrono::steady_clock::now(); });
  reduce_loads(sim, &rates, view, false);
  team_single([&] {
    for (std::size_t k = 0; k < bodies_.size(); ++k) {
      auto& b = bodies_[k];
      if (replace) {  // a2 rebuilt (first step, dt change, restart): R2 is this reaction
        b.mid_force = b.loads.fluid_force;
        b.mid_torque = b.loads.fluid_torque;
      }
      r1_force_[k] = b.loads.fluid_force;
      r1_torque_[k] = b.loads.fluid_torque;
    }
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  });
}

template <int D>
void RigidBodies<D>::variational_trial(Simulation<D>& sim, double dt, double alpha, bool predictor, Vec<D>* v_out) {
  const Eigen::Vector3d g = v3<D>(sim.rates().body_acceleration());
  team_single([&] {
    const double w1 = predictor ? 0.0 : 1 - alpha, w2 = predictor ? 1.0 : alpha;
    for (std::size_t k = 0; k < bodies_.size(); ++k) {
      const RigidBody& b = bodies_[k];
      const BodyLoads& q = at_qk_[k];
      // eq. (63) for the bodies: the reaction of (1 - alpha) a1 + alpha a2 (+ Gamma_k), contact, moorings
      const Eigen::Vector3d F = w1 * r1_force_[k] + w2 * b.mid_force + q.fluid_force + q.contact_force +
                                q.mooring_force + b.mp.mass * g;
      const Eigen::Vector3d T = w1 * r1_torque_[k] + w2 * b.mid_torque + q.fluid_torque + q.contact_torque +
                                q.mooring_torque;
      trial_[k] = b;
      step_body(trial_[k], F, T, dt, 1.0);  // V_{k+1/2} = V_{k-1/2} + dt A, X_{k+1} = X_k + dt V_{k+1/2}
      trial_[k].loads.fluid_force = w1 * r1_force_[k] + w2 * b.mid_force + q.fluid_force;
      trial_[k].loads.fluid_torque = w1 * r1_torque_[k] + w2 * b.mid_torque + q.fluid_torque;
      trial_[k].loads.contact_force = q.contact_force;
      trial_[k].loads.contact_torque = q.contact_torque;
      trial_[k].loads.mooring_force = q.mooring_force;
      trial_[k].loads.mooring_torque = q.mooring_torque;
      chord_x_[k] = (trial_[k].x - b.x) / dt;
      chord_r_[k] = (trial_[k].q.toRotationMatrix() - b.q.toRotationMatrix()) / dt;
    }
  });
  // each body particle's chord velocity (x_{k+1} - x_k) / dt: its velocity in the fixed point (the fluid's
  // v_{k+1/2} is the same chord); offsets from the body frame, not x_i (a periodic axis may have wrapped it)
  auto& f = sim.fields();
  for_each_particle(sim.size(), [&](std::size_t i) {
    const int k = rigid_of(f.body[i]);
    if (k < 0 || f.kind[i] == 0) return;
    v_out[i] = vd<D>(chord_x_[std::size_t(k)] + chord_r_[std::size_t(k)] * v3<D>((*local_)[i]));
  });
}

template <int D>
void RigidBodies<D>::variational_accept(Simulation<D>& sim, double dt) {
  team_single([&] {
    for (std::size_t k = 0; k < bodies_.size(); ++k) {
      const Eigen::Vector3d r1f = r1_force_[k], r1t = r1_torque_[k];
      bodies_[k] = trial_[k];
      bodies_[k].mid_force = r1f;  // a1 becomes the next step's a2
      bodies_[k].mid_torque = r1t;
      check_in_domain(bodies_[k], sim.time() + dt);
    }
  });
}

template <int D>
void RigidBodies<D>::advance(Simulation<D>& sim, double dt, double drift) {
  team_single([&] { started_ = std::chrono::steady_clock::now(); });
  reduce_loads(sim);
  const Eigen::Vector3d g = v3<D>(sim.rates().body_acceleration());
  team_single([&] {
    for (auto& b : bodies_) {
      const BodyLoads& l = b.loads;
      const Eigen::Vector3d F = l.fluid_force + l.contact_force + l.mooring_force + b.mp.mass * g;
      const Eigen::Vector3d T = l.fluid_torque + l.contact_torque + l.mooring_torque;
      step_body(b, F, T, dt, drift);
      check_in_domain(b, sim.time() + dt);
    }
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  });
}

template <int D>
Eigen::Vector3d RigidBodies<D>::momentum() const {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (const auto& b : bodies_) p += b.mp.mass * b.v;
  return p;
}

template <int D>
Eigen::Vector3d RigidBodies<D>::angular_momentum() const {
  Eigen::Vector3d l = Eigen::Vector3d::Zero();
  for (const auto& b : bodies_) {
    const Eigen::Matrix3d R = b.q.toRotationMatrix();
    l += b.x.cross(b.mp.mass * b.v) + R * b.mp.inertia * R.transpose() * b.w;  // orbital + spin about the com
  }
  return l;
}

template <int D>
double RigidBodies<D>::kinetic_energy() const {
  double e = 0;
  for (const auto& b : bodies_) {
    const Eigen::Matrix3d R = b.q.toRotationMatrix();
    e += 0.5 * b.mp.mass * b.v.squaredNorm() + 0.5 * b.w.dot(R * b.mp.inertia * R.transpose() * b.w);
  }
  return e;
}

template <int D>
double RigidBodies<D>::potential_energy(const Eigen::Vector3d& g) const {
  double e = 0;
  for (const auto& b : bodies_) e -= b.mp.mass * g.dot(b.x);
  return e;
}

namespace {
nlohmann::json to_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d from_json(const nlohmann::json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()}; }
}  // namespace

template <int D>
nlohmann::json RigidBodies<D>::save_state() const {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& b : bodies_)
    a.push_back({{"body", b.scene_index}, {"x", to_json(b.x)}, {"v", to_json(b.v)}, {"w", to_json(b.w)},
                 {"L", to_json(b.L)}, {"q", {b.q.w(), b.q.x(), b.q.y(), b.q.z()}}, {"acc", to_json(b.acc)}, {"mid_force", to_json(b.mid_force)}, {"mid_torque", to_json(b.mid_torque)},
                 {"alpha", to_json(b.alpha)}});
  return a;
}

template <int D>
void RigidBodies<D>::restore_state(const nlohmann::json& j) {
  if (!j.is_array() || j.size() != bodies_.size())
    throw InputError("checkpoint: rigid body state for " + std::to_string(bodies_.size()) + " bodies expected");
  for (std::size_t k = 0; k < bodies_.size(); ++k) {
    auto& b = bodies_[k];
    const auto& e = j[k];
    if (e.at("body").get<int>() != b.scene_index) throw InputError("checkpoint: rigid bodies do not match the scene");
    b.x = from_json(e.at("x"));
    b.v = from_json(e.at("v"));
    b.w = from_json(e.at("w"));
    b.L = from_json(e.at("L"));
    const auto& q = e.at("q");
    b.q = Eigen::Quaterniond(q.at(0).get<double>(), q.at(1).get<double>(), q.at(2).get<double>(), q.at(3).get<double>());
    b.acc = from_json(e.at("acc"));
    b.alpha = from_json(e.at("alpha"));
    if (e.contains("mid_force")) {  // checkpoints before the variational coupling have none
      b.mid_force = from_json(e.at("mid_force"));
      b.mid_torque = from_json(e.at("mid_torque"));
    }
  }
}

template class RigidBodies<2>;
template class RigidBodies<3>;

}  // namespace varsph::bodies
