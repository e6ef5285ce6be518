#include <omp.h>

#include <cstdio>
#include <cstdlib>

#include "app/commands.hpp"
#include "app/default_threads.hpp"
#include "scene/sanity.hpp"
#include "scene/scene.hpp"
#include "sim/particle_budget.hpp"
#include "sim/run_estimate.hpp"
#include "sim/scene_summary.hpp"

namespace varsph {

int command_info(const CommandArgs& a) {
  const scene::Scene s = scene::parse_scene(a.scene, a.overrides);
  if (a.threads > 0) omp_set_num_threads(a.threads);
  else if (!std::getenv("OMP_NUM_THREADS"))  // what `varsph run` would take here now (app/default_threads.hpp)
    omp_set_num_threads(threads_for_load(std::max(1, omp_get_num_procs()), load_average()));
  // first, in a fresh process: its memory is measured as the growth of the resident size (sim/run_estimate)
  const RunEstimate e = estimate_run(s, a.overrides, a.limits);
  double planned = 0;  // box, tank, sphere and point bodies, from their size (mesh bodies: not without the mesh)
  for (std::size_t b = 0; b < s.bodies.size(); ++b) planned += estimate_body_particles(s, b);
  if (planned <= a.limits.calibrate_max_particles) {
    std::fputs(describe_scene(s).c_str(), stdout);
  } else {  // sampling it would take long: the estimate below comes from a coarser copy (issue 35)
    std::printf("scene              %s (%s)\ndimension          %d\nsetup              %s\nparticles          about %.4g planned "
                "(from the bodies' sizes; not sampled: more than --calibrate-max %.4g)\ndx                 %g m\n",
                s.name.c_str(), s.file.string().c_str(), s.dimension, setup_line(s).c_str(), planned, a.limits.calibrate_max_particles,
                s.spacing);
  }
  // unusual but accepted values (scene/sanity.hpp; docs/scene.md "Sanity checks")
  std::vector<std::string> warnings = scene::check_sanity(s);
  // what the run will cost (sim/run_estimate.hpp), with warnings past the limits
  std::fputs(describe_estimate(s, e, a.limits, warnings).c_str(), stdout);
  if (warnings.empty()) std::fputs("warnings           none\n", stdout);
  for (const auto& w : warnings) std::printf("warning            %s\n", w.c_str());
  return 0;
}

}  // namespace varsph
