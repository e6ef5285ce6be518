// `varsph study SCENE.json [MORE.json ...]`: speed against error for a scene (docs/study.md).
#include <CLI/CLI.hpp>

#include "app/commands.hpp"
#include "study/study.hpp"

namespace varsph {

CLI::App* add_study_command(CLI::App& app, StudyCli& c) {
  auto* s = app.add_subcommand(
      "study",
      "Run a scene at several resolutions (each level a `varsph run`) and report, for every probe column and the "
      "global series (energies, momentum, max speed, front, forces), the observed order, a Richardson estimate of "
      "the converged value and each level's error with the flags that make it untrustworthy, beside each level's "
      "cost (wall and CPU seconds, particle-steps, peak memory). Writes DIR/study.json, study.csv, levels.csv, "
      "report.md, series/, plots/ and the runs (levels/, ablation/). docs/study.md");
  s->add_option("scenes", c.scenes,
                "Scene file; or several, one per level, coarsest first (scenes generated per resolution)")
      ->required();
  s->add_option("-o,--output", c.output, "Study directory (default runs/NAME_study)");
  s->add_option("--set", c.o.overrides, "Override a scene key in every run: KEY=VALUE (VALUE as JSON), repeatable")
      ->allow_extra_args(false);
  s->add_option("--refine", c.refine,
                "both: dx with h/dx fixed and dt with it (the scene's CFL number); dx: dx only, every level at the "
                "finest level's step; dt: dt only")
      ->default_val("both");
  s->add_option("--levels", c.o.levels, "Number of levels, 2 to 8 (the scene's resolution is the coarsest)")
      ->default_val(3);
  s->add_option("--ratio", c.ratio, "Refinement ratio between levels: 2, sqrt2 or a number in (1.05, 4]")
      ->default_val("2");
  s->add_option("--dx", c.o.coarsest_dx, "Spacing of the coarsest level [m] (default the scene's; h/dx and the "
                                         "scene's CFL number are kept)");
  s->add_option("--threads", c.o.threads, "OpenMP threads of every run (default: the run's default)")
      ->check(CLI::PositiveNumber);
  s->add_option("--budget", c.o.budget_minutes,
                "Wall-time budget in minutes: after the coarsest level, choose the ratio, number of levels and "
                "ablation level that refine furthest within it, predicted from that level's cost per particle-step");
  s->add_option("--ablate", c.o.ablate,
                "TERM[,TERM...]: physics.* term (removed if the scene names it, added with defaults if not), "
                "gravity, boundary.model, integrator.type, integrator.alpha, physics.density (one run per "
                "alternative), or KEY=VALUE (that alternative); run at the finest affordable level and judged "
                "against its discretisation error")
      ->delimiter(',')
      ->allow_extra_args(false);
  s->add_option("--tolerance", c.o.tolerances,
                "5% or 0.05 (relative, every quantity) or QUANTITY=VALUE[%] with * wildcards, e.g. "
                "'p_wall.peak*=500'; reports the cheapest level that meets it (repeatable)")
      ->allow_extra_args(false);
  s->add_option("--window", c.windows, "Time window T0:T1 [s] for means, peaks and series norms (repeatable; default "
                                       "the whole run)")
      ->allow_extra_args(false);
  s->add_option("--norm", c.o.norm, "Norm of whole series: l1, l2 (RMS) or linf")->default_val("l2");
  s->add_flag("--no-extra-probes", c.no_extra_probes,
              "Do not add a front probe and a force probe per boundary body when the scene lacks them");
  s->add_flag("--no-plots", c.no_plots, "Do not run the plot script (pipelines/study/plot_study.py)");
  s->add_flag("--overwrite", c.o.overwrite, "Replace an existing non-empty study directory");
  s->add_flag("--reuse", c.o.reuse, "Keep finished runs of an earlier study in DIR whose resolved scene is the same");
  s->add_flag("--quiet", c.o.quiet, "Print only errors");
  return s;
}

int command_study(StudyCli& c, const std::vector<std::string>& argv) {
  c.o.scenes.assign(c.scenes.begin(), c.scenes.end());
  c.o.output = c.output;
  c.o.refine = study::parse_refine(c.refine);
  c.o.ratio = study::parse_ratio(c.ratio);
  c.o.ratio_given = c.ratio_given;
  for (const auto& w : c.windows) c.o.windows.push_back(study::parse_window(w));
  c.o.plots = !c.no_plots;
  c.o.extra_probes = !c.no_extra_probes;
  c.o.command_line = argv;
  return study::run_study(c.o);
}

}  // namespace varsph
