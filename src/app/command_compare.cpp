// `varsph compare RUN_A RUN_B [-o DIR]`: deviation between two runs, seed eq. (70) (CONTRACT.md).
#include <cstdio>

#include "app/commands.hpp"
#include "io/deviation.hpp"

namespace varsph {

int command_compare(const CommandArgs& a) {
  io::CompareOptions o;
  o.run_a = a.run_a;
  o.run_b = a.run_b;
  o.overwrite = a.overwrite;
  // default: RUN_A/post/deviation_vs_<name of RUN_B>
  const auto b_name = std::filesystem::path(a.run_b).lexically_normal().filename().string();
  o.output = a.output.empty()
                 ? std::filesystem::path(a.run_a) / "post" / ("deviation_vs_" + (b_name.empty() ? "B" : b_name))
                 : std::filesystem::path(a.output);
  const auto rows = io::compare_runs(o);
  if (!a.quiet) {
    double dmax = 0;
    for (const auto& r : rows) dmax = std::max(dmax, r.d_max);
    std::printf("varsph: compared %zu frames (t = %g .. %g s); largest D = %.6g m -> %s\n", rows.size(),
                rows.front().time, rows.back().time, dmax, (o.output / "deviation.csv").string().c_str());
    // particles a run removed (health.*) are matched by id and left out of D; say how many
    const auto& last = rows.back();
    if (last.only_a > 0 || last.only_b > 0)
      std::printf("varsph: at t = %g s, %ld fluid particles matched by id, %ld only in %s, %ld only in %s "
                  "(removed by the other run's health rules; columns matched, only_a, only_b)\n",
                  last.time, last.matched, last.only_a, a.run_a.c_str(), last.only_b, a.run_b.c_str());
  }
  return 0;
}

}  // namespace varsph
