// Resolves the scene's kernel x viscosity x wall model into one compiled Rates implementation.
#include <vector>

#include "kernels/cubic_spline.hpp"
#include "kernels/gaussian.hpp"
#include "kernels/paper_literal.hpp"
#include "kernels/tabulated.hpp"
#include "kernels/wendland_c2.hpp"
#include "physics/pair_loop.hpp"
#include "physics/passes.hpp"
#include "physics/rates.hpp"

namespace varsph::physics {
namespace {

template <int D, class Kernel, class Viscosity, BoundaryModel M>
class RatesImpl final : public Rates<D> {
 public:
  RatesImpl(const PhysicsParams<D>& p, Kernel kernel, Viscosity visc)
      : p_(p), W_(kernel), visc_(visc), wall_(p.wall_D, p.wall_r0, p.wall_n1, p.wall_n2) {}

  void density_rate(const NeighborGrid<D>& g, const ParticleView<D>& s, Real* drho) const override {
    DensityRatePass<D, Kernel, M> pass{W_, s, drho};
    for_each_particle_pairs<D>(g, s.x, W_.support(), pass);
  }
  void summation_density(const NeighborGrid<D>& g, const ParticleView<D>& s, Real* rho) const override {
    SummationDensityPass<D, Kernel, M> pass{W_, s, rho};
    for_each_particle_pairs<D>(g, s.x, W_.support(), pass);
  }
  void acceleration(const NeighborGrid<D>& g, const ParticleView<D>& s, Vec<D>* a) const override {
    AccelerationPass<D, Kernel, Viscosity, M> pass{W_, visc_, wall_, s, p_.gravity, a, pressure_terms(s)};
    for_each_particle_pairs<D>(g, s.x, W_.support(), pass);
  }
  void boundary_reaction(const NeighborGrid<D>& g, const ParticleView<D>& s, Vec<D>* force) const override {
    using Acc = AccelerationPass<D, Kernel, Viscosity, M>;
    const Acc acc{W_, visc_, wall_, s, p_.gravity, nullptr, pressure_terms(s)};
    BoundaryReactionPass<D, Acc> pass{acc, s, force};
    for_each_particle_pairs<D>(g, s.x, W_.support(), pass);
  }
  Real support() const override { return W_.support(); }
  // p / rho^2 of every particle, once per pass instead of once per pair (scratch grows once)
  const Real* pressure_terms(const ParticleView<D>& s) const {
    p_over_rho2_.resize(s.size());
    Real* pr = p_over_rho2_.data();
    for_each_particle(s.size(), [&](std::size_t i) { pr[i] = s.p[i] / (s.rho[i] * s.rho[i]); });
    return pr;
  }
  Real kernel_w(Real r) const override { return r < W_.support() ? W_.w_r2(r * r) : Real(0); }

 private:
  PhysicsParams<D> p_;
  Kernel W_;
  Viscosity visc_;
  RepulsiveWall wall_;
  mutable std::vector<Real> p_over_rho2_;  // scratch of the acceleration pass
};

template <int D, class Kernel, class Viscosity>
std::unique_ptr<Rates<D>> with_wall(const PhysicsParams<D>& p, Kernel k, Viscosity v) {
  switch (p.boundary) {
    case BoundaryModel::Repulsive: return std::make_unique<RatesImpl<D, Kernel, Viscosity, BoundaryModel::Repulsive>>(p, k, v);
    case BoundaryModel::Dynamic: return std::make_unique<RatesImpl<D, Kernel, Viscosity, BoundaryModel::Dynamic>>(p, k, v);
  }
  return nullptr;
}

template <int D, class Kernel>
std::unique_ptr<Rates<D>> with_viscosity(const PhysicsParams<D>& p, Kernel k) {
  if (p.artificial_viscosity)
    return with_wall<D>(p, k, ArtificialViscosity(p.av_alpha, p.av_beta, p.c0, p.h, p.av_eps));
  return with_wall<D>(p, k, NoViscosity{});
}

}  // namespace

template <int D>
std::unique_ptr<Rates<D>> make_rates(const PhysicsParams<D>& p) {
  using kernels::KernelType;
  if (p.kernel_tabulated) return with_viscosity<D>(p, kernels::Tabulated<D>(p.kernel, p.h, p.kernel_l));
  switch (p.kernel) {
    case KernelType::Gaussian: return with_viscosity<D>(p, kernels::Gaussian<D>(p.h));
    case KernelType::CubicSpline: return with_viscosity<D>(p, kernels::CubicSpline<D>(p.h));
    case KernelType::WendlandC2: return with_viscosity<D>(p, kernels::WendlandC2<D>(p.h));
    case KernelType::PaperLiteral: return with_viscosity<D>(p, kernels::PaperLiteral<D>(p.h, p.kernel_l));
  }
  return nullptr;
}

template std::unique_ptr<Rates<2>> make_rates<2>(const PhysicsParams<2>&);
template std::unique_ptr<Rates<3>> make_rates<3>(const PhysicsParams<3>&);

}  // namespace varsph::physics
