#include "sim/sample_report.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "sim/frame_export.hpp"
#include "sim/simulation.hpp"

namespace varsph {
namespace {

template <int D>
std::string sample(const scene::Scene& s, const std::filesystem::path& dir) {
  Simulation<D> sim(s);
  const auto path = dir / (s.name + "_particles.vtu");
  io::write_vtu(path.string(), frame_from(sim, {"kind", "normal", "id", "mass", "density", "body"}, true));
  // nearest-neighbour distance of every particle, by kind, through the grid (support >= 1.2 dx)
  const auto& grid = sim.grid();
  const auto& x = sim.fields().x.data;
  const auto& kind = sim.fields().kind.data;
  double mn[2] = {1e300, 1e300}, mx[2] = {0, 0}, sum[2] = {0, 0};
  std::size_t cnt[2] = {0, 0};
  for (const auto& blk : grid.blocks())
    for (std::uint32_t i = blk.begin; i < blk.end; ++i) {
      double best = std::numeric_limits<double>::infinity();
      for (std::uint32_t r = blk.nbr_begin; r < blk.nbr_end; ++r) {
        const auto nr = grid.ranges()[r];
        for (std::uint32_t j = nr.begin; j < nr.end; ++j)
          if (j != i && kind[j] == kind[i])
            best = std::min(best, double((x[i] - grid.shift(nr.shift) - x[j]).norm()));
      }
      if (!std::isfinite(best)) continue;
      const int k = kind[i] == 0 ? 0 : 1;
      mn[k] = std::min(mn[k], best);
      mx[k] = std::max(mx[k], best);
      sum[k] += best;
      ++cnt[k];
    }
  std::ostringstream o;
  o.precision(5);
  o << "scene        " << s.name << "\n"
    << "particles    " << sim.count(0) << " fluid, " << sim.count(1) << " boundary\n"
    << "written      " << path.string() << "\n";
  // per body: count and bounding box, so that a mesh's scale / rotate_deg / translate can be checked before
  // a run (issue 35); the box is of particle centres
  const auto& body = sim.fields().body.data;
  const std::size_t nb = s.bodies.size();
  std::vector<std::size_t> bc(nb, 0);
  std::vector<Vec<D>> lo(nb, Vec<D>::Constant(std::numeric_limits<Real>::max())),
      hi(nb, Vec<D>::Constant(std::numeric_limits<Real>::lowest()));
  for (std::size_t i = 0; i < sim.size(); ++i) {
    const auto b = std::size_t(body[i]);
    if (b >= nb) continue;
    ++bc[b];
    lo[b] = lo[b].cwiseMin(x[i]);
    hi[b] = hi[b].cwiseMax(x[i]);
  }
  auto vec = [](const Vec<D>& v) {
    std::ostringstream t;
    t.precision(5);
    t << "[";
    for (int a = 0; a < D; ++a) t << (a ? ", " : "") << double(v[a]);
    return t.str() + "]";
  };
  for (std::size_t b = 0; b < nb; ++b) {
    const auto& spec = s.bodies[b];
    std::string what = spec.kind + " " + spec.shape;
    if (spec.shape == "mesh" && spec.mesh.contains("mesh") && spec.mesh["mesh"].is_string())
      what += " " + spec.mesh["mesh"].get<std::string>();
    o << "body " << b << std::string(b < 10 ? 7 : 6, ' ') << what << ": " << bc[b] << " particles";
    if (bc[b]) o << ", centres in " << vec(lo[b]) << " .. " << vec(hi[b]) << " m";
    o << "\n";
  }
  const char* names[2] = {"fluid", "boundary"};
  for (int k = 0; k < 2; ++k)
    if (cnt[k])
      o << "spacing      " << names[k] << ": nearest neighbour min " << mn[k] / s.spacing << " dx, mean "
        << sum[k] / double(cnt[k]) / s.spacing << " dx, max " << mx[k] / s.spacing << " dx (dx = " << s.spacing
        << " m)\n";
  return o.str();
}

}  // namespace

std::string write_sampled_particles(const scene::Scene& s, const std::filesystem::path& dir) {
  return s.dimension == 2 ? sample<2>(s, dir) : sample<3>(s, dir);
}

}  // namespace varsph
