#pragma once
// The physics passes of a distributed run: the scene's compiled Rates, unchanged, behind a wrapper that
// first copies the owners' current values of what the pass reads into the ghosts (Domain::refresh).
// Integrators call it exactly as in one process, at whatever configuration they evaluate (the
// variational integrator's midpoints and every fixed-point iterate included): the exchange follows the
// arrays of the ParticleView they pass. One message per neighbour rank and pass.
#include <memory>
#include <type_traits>
#include <vector>

#include "parallel/domain.hpp"
#include "physics/rates.hpp"

namespace varsph::parallel {

// What a pass reads from neighbours, sent to the ghosts: positions, velocities, and the state
// (densities, pressures, the dummy walls' velocities).
constexpr int kHaloPositions = 1, kHaloVelocities = 2, kHaloState = 4;

// Refreshes the ghosts of the view's arrays. The views' arrays are the store's fields or an
// integrator's registered scratch: writable memory that the ParticleView shows read-only.
template <int D>
void refresh_view(Domain<D>& domain, const physics::ParticleView<D>& s, int what, std::vector<HaloArray>& a) {
  a.clear();
  auto add = [&](auto span) {
    using T = typename decltype(span)::element_type;
    if (!span.empty()) a.push_back({const_cast<std::remove_const_t<T>*>(span.data()), sizeof(T), span.size()});
  };
  if (what & kHaloPositions) add(s.x);
  if (what & kHaloVelocities) add(s.v);
  if (what & kHaloState) {
    add(s.rho);
    add(s.p);
    add(s.wall_v);
    add(s.normal);  // moving extrapolated walls turn their normals (read by the wall part of AV)
  }
  domain.refresh(a);
}

template <int D>
class HaloRates final : public physics::Rates<D> {
 public:
  HaloRates(std::unique_ptr<physics::Rates<D>> inner, Domain<D>& domain) : inner_(std::move(inner)), domain_(domain) {
    // the shifting pass's global speed ("max" mode) is a maximum over every rank's particles
    Communicator* comm = &domain.comm();
    inner_->global_max = [comm](Real v) { return Real(comm->max(double(v))); };
  }

  static constexpr int Positions = kHaloPositions, Velocities = kHaloVelocities, State = kHaloState;
  void refresh(const physics::ParticleView<D>& s, int what) const { refresh_view(domain_, s, what, arrays_); }
  static constexpr int kAll = Positions | Velocities | State;

  void density_rate(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Real* drho) const override {
    refresh(s, kAll);
    inner_->density_rate(g, s, drho);
  }
  void summation_density(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Real* rho) const override {
    refresh(s, Positions);  // masses and kinds do not change between rebins
    inner_->summation_density(g, s, rho);
  }
  void acceleration(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Vec<D>* a) const override {
    refresh(s, kAll);
    inner_->acceleration(g, s, a);
  }
  void density_rate_and_acceleration(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Real* drho,
                                     Vec<D>* a) const override {
    refresh(s, kAll);
    inner_->density_rate_and_acceleration(g, s, drho, a);
  }
  bool fused() const override { return inner_->fused(); }
  void boundary_reaction(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Vec<D>* force) const override {
    refresh(s, kAll);
    inner_->boundary_reaction(g, s, force);
  }
  Real support() const override { return inner_->support(); }
  Real kernel_w(Real r) const override { return inner_->kernel_w(r); }
  void set_time(double t) override { inner_->set_time(t); }
  Vec<D> body_acceleration() const override { return inner_->body_acceleration(); }
  bool update_walls(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, const physics::WallGeometry<D>& geo,
                    Real* p, Real* rho, Vec<D>* wall_v) const override {
    refresh(s, kAll);  // the wall's own geometry (normal, distance, acceleration) is read for owned walls only
    return inner_->update_walls(g, s, geo, p, rho, wall_v);
  }
  bool xsph_enabled() const override { return inner_->xsph_enabled(); }
  void xsph(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Vec<D>* out) const override {
    refresh(s, kAll);
    inner_->xsph(g, s, out);
  }
  bool shifting_enabled() const override { return inner_->shifting_enabled(); }
  void shifting(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Real dt, Vec<D>* out) const override {
    refresh(s, Positions | Velocities);
    inner_->shifting(g, s, dt, out);
  }

 private:
  std::unique_ptr<physics::Rates<D>> inner_;
  Domain<D>& domain_;
  mutable std::vector<HaloArray> arrays_;
};

}  // namespace varsph::parallel
