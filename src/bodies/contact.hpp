#pragma once
// Contact of rigid bodies with each other and with every other boundary body: a spring-dashpot between
// boundary particles of different bodies closer than the contact distance d (the discrete-element
// model of Cundall & Strack 1979, normal part only), f = max(0, k (d - r) - gamma v_n) n, n = x_ij / r.
// k defaults to rho0 c0^2 dx^(d-2) (the fluid's own stiffness over one particle face and one spacing);
// gamma follows from the pair's restitution e with the particle mass m: gamma = 2 zeta sqrt(m k),
// zeta = -ln e / sqrt(pi^2 + ln^2 e). Runs over the particles of rigid bodies only; a pair of two
// rigid bodies is computed from both sides with the same formula (x_ji = -x_ij, v_ji = -v_ij), so the
// two forces are exact opposites.
#include <cstdint>

#include "core/real.hpp"
#include "physics/rates.hpp"

namespace varsph::bodies {

template <int D>
struct ContactPass {
  const Vec<D>* x;
  const Vec<D>* v;
  const std::int32_t* kind;
  const std::int32_t* body;
  physics::BoundaryFilter rigid;  // the particles it runs over
  Real d2, d, k, gamma;
  Vec<D>* out;
  bool active(std::size_t i) const { return kind[i] != 0 && rigid.selects(i); }
  Vec<D> begin(std::size_t) const { return Vec<D>::Zero(); }
  void pair(Vec<D>& f, std::size_t i, std::size_t j, const Vec<D>& xij, Real r2) const {
    if (kind[j] == 0 || body[j] == body[i] || r2 >= d2 || r2 <= Real(0)) return;
    const Real r = std::sqrt(r2);
    const Vec<D> n = xij / r;
    const Real fn = k * (d - r) - gamma * (v[i] - v[j]).dot(n);
    if (fn > Real(0)) f += fn * n;  // no adhesion
  }
  void end(std::size_t i, const Vec<D>& f) const { out[i] = f; }
};

}  // namespace varsph::bodies
