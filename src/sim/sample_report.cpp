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
