#pragma once
// The physics passes of a distributed run: the scene's compiled Rates, unchanged, behind a wrapper that
// first copies the owners' current values of what the pass reads into the ghosts (Domain::refresh).
// Integrators call it exactly as in one process, at whatever configuration they evaluate (the
// variational integrator's midpoints and every fixed-point iterate included): the exchange follows the
// arrays of the ParticleView they pass. One message per neighbour rank and pass.
//
// Overlap: the grid rebin() built is also split into interior blocks (no ghost in their stencil) and
// boundary blocks (block_split.hpp). A pass whose sweep is block-local (Rates::splits_by_blocks) then
// posts the refresh, sweeps the interior blocks, waits, and sweeps the boundary blocks: each particle
// still sums its own neighbours in the same order, so the results are those of the one sweep, bit for
// bit. Ghost positions and the grid are valid at that point (a refresh only changes values), which is
// what makes this possible; the exchanges inside rebin() (migration, ghost selection) decide which
// particles a rank holds and how the grid is built, so no sweep can start before they end.
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
void collect_view(const physics::ParticleView<D>& s, int what, std::vector<HaloArray>& a) {
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
}
template <int D>
void refresh_view(Domain<D>& domain, const physics::ParticleView<D>& s, int what, std::vector<HaloArray>& a) {
  collect_view(s, what, a);
  domain.refresh(a);
}

template <int D>
class HaloRates final : public physics::Rates<D> {
 public:
  HaloRates(std::unique_ptr<physics::Rates<D>> inner, Domain<D>& domain) : inner_(std::move(inner)), domain_(domain) {
    // the shifting pass's global speed ("max" mode) is a maximum over every rank's particles
    Communicator* comm = &domain.comm();
    inner_->global_max = [comm](Real v) { return Real(comm->max(double(v))); };
    // Antuono's density pass reads its ghost neighbours' renormalised gradients: their owners' values
    Domain<D>* dom = &domain;
    inner_->refresh_ghosts = [dom](void* data, std::size_t bytes, std::size_t count) {
      const HaloArray a{data, bytes, count};
      dom->refresh(std::span<const HaloArray>(&a, 1));
    };
  }

  static constexpr int Positions = kHaloPositions, Velocities = kHaloVelocities, State = kHaloState;
  void refresh(const physics::ParticleView<D>& s, int what) const { refresh_view(domain_, s, what, arrays_); }
  static constexpr int kAll = Positions | Velocities | State;

  void density_rate(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Real* drho) const override {
    split(g, s, kAll, [&](const NeighborGrid<D>& part, const View& v) { inner_->density_rate(part, v, drho); });
  }
  void summation_density(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Real* rho) const override {
    // masses and kinds do not change between rebins
    split(g, s, Positions, [&](const NeighborGrid<D>& part, const View& v) { inner_->summation_density(part, v, rho); });
  }
  void acceleration(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Vec<D>* a) const override {
    split(g, s, kAll, [&](const NeighborGrid<D>& part, const View& v) { inner_->acceleration(part, v, a); });
  }
  void density_rate_and_acceleration(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Real* drho,
                                     Vec<D>* a) const override {
    split(g, s, kAll, [&](const NeighborGrid<D>& part, const View& v) {
      inner_->density_rate_and_acceleration(part, v, drho, a);
    });
  }
  bool fused() const override { return inner_->fused(); }
  const char* simd() const override { return inner_->simd(); }
  bool splits_by_blocks() const override { return inner_->splits_by_blocks(); }
  void boundary_reaction(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Vec<D>* force,
                         physics::BoundaryFilter only) const override {
    refresh(s, kAll);  // probes and rigid bodies: not split
    inner_->boundary_reaction(g, s, force, only);
  }
  Real support() const override { return inner_->support(); }
  Real kernel_w(Real r) const override { return inner_->kernel_w(r); }
  void set_time(double t) override { inner_->set_time(t); }
  Vec<D> body_acceleration() const override { return inner_->body_acceleration(); }
  bool update_walls(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, const physics::WallGeometry<D>& geo,
                    Real* p, Real* rho, Vec<D>* wall_v) const override {
    // the wall's own geometry (normal, distance, acceleration) is read for owned walls only
    bool done = false;
    split(g, s, kAll, [&](const NeighborGrid<D>& part, const View& v) {
      done = inner_->update_walls(part, v, geo, p, rho, wall_v);
    });
    return done;
  }
  bool xsph_enabled() const override { return inner_->xsph_enabled(); }
  void xsph(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Vec<D>* out) const override {
    split(g, s, kAll, [&](const NeighborGrid<D>& part, const View& v) { inner_->xsph(part, v, out); });
  }
  bool shifting_enabled() const override { return inner_->shifting_enabled(); }
  void shifting(const NeighborGrid<D>& g, const physics::ParticleView<D>& s, Real dt, Vec<D>* out) const override {
    refresh(s, Positions | Velocities);  // not split: its global speed is a reduction over ranks
    inner_->shifting(g, s, dt, out);
  }

 private:
  using View = physics::ParticleView<D>;
  // The view's first n particles: what the interior blocks read (their stencils hold owned particles
  // only). Per-particle work of the pass (p / rho^2, volumes) then skips the ghosts, and the neighbour
  // list cache's key (positions and kinds of the view) does not see the ghosts' values, which the refresh
  // in flight is about to replace.
  static View first(const View& s, std::size_t n) {
    auto cut = [n](auto span) { return span.empty() ? span : span.first(n); };
    return {cut(s.x), cut(s.v), cut(s.rho), cut(s.p), cut(s.mass), cut(s.kind), cut(s.wall_v), cut(s.normal)};
  }
  // refresh + run(g), or, where the pass allows it, post + run(interior) + wait + run(boundary)
  template <class Run>
  void split(const NeighborGrid<D>& g, const View& s, int what, Run&& run) const {
    const BlockSplit<D>* parts = domain_.split_for(g);
    if (!parts || !inner_->splits_by_blocks()) {
      refresh(s, what);
      run(g, s);
      return;
    }
    arrays_.clear();
    collect_view(s, what, arrays_);
    domain_.begin_refresh(arrays_);
    try {
      run(parts->part(0), first(s, domain_.owned()));
    } catch (...) {
      domain_.finish_refresh();  // no request left pending
      throw;
    }
    domain_.finish_refresh();
    domain_.count_overlapped_refresh();
    run(parts->part(1), s);
  }

  std::unique_ptr<physics::Rates<D>> inner_;
  Domain<D>& domain_;
  mutable std::vector<HaloArray> arrays_;
};

}  // namespace varsph::parallel
