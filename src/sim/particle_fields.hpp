#pragma once
// The particle arrays every simulation registers, with their roles. Integrators and modules add their
// own (previous positions, midpoint densities, ...) through the same registry.
#include <cstdint>

#include "core/particle_store.hpp"

namespace varsph {

template <int D>
struct ParticleFields {
  explicit ParticleFields(ParticleStore& s)
      : x(s.add<Vec<D>>("position", {.exported = false})),
        v(s.add<Vec<D>>("velocity", {.exported = true})),
        a(s.add<Vec<D>>("acceleration", {.exported = false, .checkpointed = false})),
        rho(s.add<Real>("density", {.exported = true})),
        drho(s.add<Real>("density_rate", {.exported = false, .checkpointed = false})),
        p(s.add<Real>("pressure", {.exported = true})),
        mass(s.add<Real>("mass", {.exported = true})),
        id(s.add<std::int64_t>("id", {.exported = true})),
        kind(s.add<std::int32_t>("kind", {.exported = true})),
        normal(s.add<Vec<D>>("normal", {.exported = true})),
        body(s.add<std::int32_t>("body", {.exported = false})) {}
  Field<Vec<D>>& x;      // positions q_k [m]
  Field<Vec<D>>& v;      // velocities [m/s] (Verlet: half-step (q_k - q_{k-1})/dt, seed eq. 60)
  Field<Vec<D>>& a;      // last accelerations [m/s^2] (scratch)
  Field<Real>& rho;      // density [kg/m^3]
  Field<Real>& drho;     // density rate [kg/m^3/s] (scratch)
  Field<Real>& p;        // pressure [Pa]
  Field<Real>& mass;     // [kg] (2D: kg per metre of depth)
  Field<std::int64_t>& id;    // stable identity across sorting, frames and restarts
  Field<std::int32_t>& kind;  // 0 fluid, 1 boundary
  Field<Vec<D>>& normal;      // outward wall normal on boundary particles, zero on fluid
  Field<std::int32_t>& body;  // index of the scene body the particle came from (probes: force on a body)
};

}  // namespace varsph
