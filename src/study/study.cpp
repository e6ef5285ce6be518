#include "study/study.hpp"

#include <algorithm>
#include <chrono>
#include <cctype>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "study/child_process.hpp"
#include "study/study_report.hpp"

namespace varsph::study {
namespace {

namespace fs = std::filesystem;

std::string iso_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

double load_now() {
  double la[1] = {0};
  return getloadavg(la, 1) == 1 ? la[0] : 0.0;
}

std::string safe_name(const std::string& s) {
  std::string o;
  for (char c : s) o += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-') ? c : '_';
  return o;
}

void prepare_study_directory(const fs::path& dir, bool overwrite, bool reuse) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError(dir.string() + ": exists and is not a directory (give another -o)");
  if (fs::exists(dir, ec) && !fs::is_empty(dir, ec) && !overwrite && !reuse)
    throw InputError(dir.string() + ": the study directory exists and is not empty (give --overwrite to replace "
                     "it, --reuse to keep its finished runs, or another -o)");
  if (overwrite && !reuse) fs::remove_all(dir, ec);
  for (const char* sub : {"", "levels", "ablation", "logs", "series", "plots"}) {
    fs::create_directories(dir / sub, ec);
    if (ec) throw IoError(dir.string() + ": cannot create the study directory: " + ec.message());
  }
}

Measured measured_of(const LevelRun& r, double baseline_rss) {
  Measured m;
  m.wall = r.child.wall_seconds;
  m.cpu = r.child.cpu_seconds;
  m.rss_mb = r.child.peak_rss_mb;
  m.steps = r.steps;
  m.fluid = r.spec.fluid;
  m.boundary = r.spec.boundary;
  m.dt_estimate = r.spec.dt_estimate;
  m.t_end = r.spec.t_end;
  m.baseline_rss_mb = baseline_rss;
  return m;
}

class StudyRunner {
 public:
  StudyRunner(const StudyOptions& o, StudyResult& R) : o_(o), R_(R), exe_(self_executable()) {}

  // Runs one level (or variant) into `dir` unless --reuse finds it finished with the same resolved scene.
  LevelRun run(const LevelSpec& spec, const std::string& name, const fs::path& dir, const Prediction* pred) {
    LevelRun r;
    r.spec = spec;
    r.dir = dir;
    const fs::path cost = R_.dir / "logs" / (name + ".json");
    const std::string resolved = resolved_scene_json(spec);
    if (o_.reuse && try_reuse(r, resolved, cost)) {
      say("%s: reused %s (finished earlier with the same resolved scene)\n", name.c_str(), dir.string().c_str());
      return r;
    }
    if (!o_.quiet) {
      std::printf("varsph study: %s: %s, %zu fluid + %zu boundary particles", name.c_str(), spec.label().c_str(),
                  spec.fluid, spec.boundary);
      if (pred && pred->wall > 0) std::printf(", predicted %.3g s wall (%.3g s CPU)", pred->wall, pred->cpu);
      std::printf(" ...\n");
      std::fflush(stdout);
    }
    std::vector<std::string> argv = {exe_.string(), "run", spec.scene.string(), "-o", dir.string(), "--overwrite",
                                     "--quiet"};
    if (o_.threads > 0) argv.insert(argv.end(), {"--threads", std::to_string(o_.threads)});
    for (const auto& s : spec.overrides) argv.insert(argv.end(), {"--set", s});
    const fs::path log = R_.dir / "logs" / (name + ".log");
    std::error_code ec;
    fs::remove(log, ec);
    r.child = run_child(argv, log);
    load_run_outputs(r);
    if (r.message.empty() && !r.ok()) r.message = last_line(log);
    nlohmann::json c = {{"exit_code", r.child.exit_code},     {"wall_seconds", r.child.wall_seconds},
                        {"cpu_seconds", r.child.cpu_seconds}, {"peak_rss_mb", r.child.peak_rss_mb},
                        {"load_before", r.child.load_before}, {"load_after", r.child.load_after},
                        {"argv", argv}};
    std::ofstream(cost) << c.dump(1) << "\n";
    if (!o_.quiet) {
      std::printf("varsph study: %s: exit %d, %.3g s wall, %.3g s CPU, %.0f MB peak, %ld steps (load %.1f-%.1f)%s%s\n",
                  name.c_str(), r.child.exit_code, r.child.wall_seconds, r.child.cpu_seconds, r.child.peak_rss_mb,
                  r.steps, r.child.load_before, r.child.load_after, r.ok() ? "" : ": ", r.ok() ? "" : r.message.c_str());
      std::fflush(stdout);
    }
    return r;
  }

  template <class... A>
  void say(const char* f, A... a) {
    if (o_.quiet) return;
    std::printf("varsph study: ");
    std::printf(f, a...);
    std::fflush(stdout);
  }

 private:
  static std::string last_line(const fs::path& log) {
    std::ifstream in(log);
    std::string line, last;
    while (std::getline(in, line))
      if (!line.empty()) last = line;
    return last;
  }

  bool try_reuse(LevelRun& r, const std::string& resolved, const fs::path& cost) {
    std::ifstream rj(r.dir / "run.json"), cj(cost);
    if (!rj || !cj) return false;
    try {
      nlohmann::json j, c;
      rj >> j;
      cj >> c;
      if (j.value("status", "") != "completed" || j["scene"] != nlohmann::json::parse(resolved)) return false;
      r.child.exit_code = 0;
      r.child.wall_seconds = c.value("wall_seconds", 0.0);
      r.child.cpu_seconds = c.value("cpu_seconds", 0.0);
      r.child.peak_rss_mb = c.value("peak_rss_mb", 0.0);
      r.child.load_before = c.value("load_before", 0.0);
      r.child.load_after = c.value("load_after", 0.0);
    } catch (const std::exception&) {
      return false;
    }
    r.reused = true;
    load_run_outputs(r);
    return true;
  }

  const StudyOptions& o_;
  StudyResult& R_;
  fs::path exe_;
};

// Budget: the plan (ratio, levels, ablation level) that refines furthest within the remaining wall time,
// predicted from the coarsest level's cost per particle-step; candidate levels are scaled, not sampled.
Plan choose_budget_plan(const StudyOptions& o, const LevelRun& l0, const Measured& m, double remaining,
                        std::size_t variants, BudgetReport& br, int& ablation_level) {
  const double avail = available_memory_mb();
  std::vector<double> ratios = o.ratio_given ? std::vector<double>{o.ratio} : std::vector<double>{2.0, std::sqrt(2.0)};
  struct Cand {
    Plan plan;
    int abl = -1;
    double wall = 0;
  };
  std::vector<Cand> fit;
  const int lmax = std::min(8, std::max(o.levels, 3) + 2);
  for (double r : ratios)
    for (int L = 2; L <= lmax; ++L) {
      Plan p = plan_levels(o, L, r, &l0.spec);
      double wall = 0;
      // level 0 is already measured unless this plan's coarsest level differs (dx refinement holds every
      // level at the finest level's step, so its coarsest level changes with the plan)
      const bool l0_same = resolved_scene_json(p.levels[0]) == resolved_scene_json(l0.spec);
      for (std::size_t k = l0_same ? 1 : 0; k < p.levels.size(); ++k) wall += predict_cost(m, p.levels[k]).wall;
      const double rss = predict_cost(m, p.levels.back()).rss_mb;
      char buf[300];
      if (avail > 0 && rss > 0.8 * avail) {
        std::snprintf(buf, sizeof buf, "ratio %.3g, %d levels: finest level needs about %.0f MB, more than 80 %% of "
                      "the %.0f MB available", r, L, rss, avail);
        br.rejected.push_back(buf);
        continue;
      }
      int abl = -1;
      double total = wall;
      for (int a = L - 1; a >= 0 && variants > 0; --a) {
        const double t = wall + double(variants) * predict_cost(m, p.levels[std::size_t(a)]).wall;
        if (t <= remaining) {
          abl = a;
          total = t;
          break;
        }
      }
      if (variants > 0 && abl < 0) total = wall + double(variants) * predict_cost(m, p.levels[0]).wall;
      if (total > remaining) {
        std::snprintf(buf, sizeof buf, "ratio %.3g, %d levels (finest dx %.4g): predicted %.0f s, more than the %.0f s "
                      "left", r, L, p.levels.back().dx, total, remaining);
        br.rejected.push_back(buf);
        continue;
      }
      fit.push_back({p, abl, total});
    }
  if (fit.empty()) {
    br.choice = "no plan of two or more levels fits the budget: the study has the coarsest level only";
    Plan p = plan_levels(o, 1, o.ratio);
    ablation_level = -1;
    return p;
  }
  // prefer three or more levels (an observed order), then the finest resolution, then the finest ablation
  // level, then the cheaper plan
  const auto better = [](const Cand& a, const Cand& b) {
    const bool a3 = a.plan.levels.size() >= 3, b3 = b.plan.levels.size() >= 3;
    if (a3 != b3) return a3;
    const double ha = a.plan.levels.back().refined, hb = b.plan.levels.back().refined;
    if (std::abs(ha - hb) > 1e-9 * hb) return ha < hb;
    if (a.abl != b.abl) return a.abl > b.abl;
    return a.wall < b.wall;
  };
  const Cand best = *std::min_element(fit.begin(), fit.end(), better);
  char buf[300];
  std::snprintf(buf, sizeof buf, "ratio %.4g, %zu levels (finest dx %.4g m), ablation at level %d: predicted %.0f s "
                "of the %.0f s left", best.plan.ratio, best.plan.levels.size(), best.plan.levels.back().dx, best.abl,
                best.wall, remaining);
  br.choice = buf;
  ablation_level = best.abl;
  StudyOptions oo = o;
  return plan_levels(oo, int(best.plan.levels.size()), best.plan.ratio);  // sampled for real
}

void geometry_notes(StudyResult& R) {
  double lo = 0, hi = 0;
  bool first = true;
  for (const auto& l : R.plan.levels) {
    if (first) lo = hi = l.fluid_mass, first = false;
    lo = std::min(lo, l.fluid_mass);
    hi = std::max(hi, l.fluid_mass);
  }
  if (hi > 0 && (hi - lo) / hi > 1e-3) {
    char buf[400];
    std::snprintf(buf, sizeof buf, "the fluid mass differs by %.2f %% between levels: the bodies are not whole "
                  "multiples of every level's dx, so the levels model slightly different geometries (part of the "
                  "measured differences is this, not resolution)", 100 * (hi - lo) / hi);
    R.notes.push_back(buf);
  }
}

}  // namespace

int run_study(const StudyOptions& opts) {
  StudyResult R;
  R.options = opts;
  const StudyOptions& o = R.options;
  R.started = iso_now();
  R.load_start = load_now();
  const auto t0 = std::chrono::steady_clock::now();
  if (o.scenes.empty()) throw InputError("varsph study: give a scene file");
  if (o.levels < 2 || o.levels > 8) throw InputError("--levels: expected 2 to 8, got " + std::to_string(o.levels));
  if (o.budget_minutes < 0) throw InputError("--budget: expected wall minutes > 0");
  R.norm = parse_norm(o.norm);
  std::vector<ToleranceSpec> tols;
  for (const auto& t : o.tolerances) tols.push_back(parse_tolerance(t));
  const double baseline_rss = current_rss_mb();

  R.plan = plan_levels(o, o.levels, o.ratio);
  // what a run would refuse is refused now, before anything is written: the coarsest level (the most likely to
  // be too coarse for its domain) and every ablation variant of it
  validate_level(R.plan.levels[0]);
  std::vector<AblationVariant> variants;
  if (!o.ablate.empty()) variants = ablation_variants(o.ablate, R.plan.levels[0], R.notes);
  R.dir = o.output.empty() ? fs::path("runs") / (R.plan.levels[0].name + "_study") : o.output;
  prepare_study_directory(R.dir, o.overwrite, o.reuse);
  install_interrupt_handlers();
  StudyRunner runner(o, R);
  const auto level_dir = [&](int k) { return R.dir / "levels" / ("L" + std::to_string(k)); };
  const auto interrupted = [&] { return interrupt_signal() != 0; };

  // the coarsest level first: its cost per particle-step predicts the others
  R.levels.push_back(runner.run(R.plan.levels[0], "L0", level_dir(0), nullptr));
  const Measured m = measured_of(R.levels[0], baseline_rss);
  const std::size_t n_variants = variants.size();
  R.ablation_level = o.ablate.empty() ? -1 : int(R.plan.levels.size()) - 1;
  if (o.budget_minutes > 0 && R.levels[0].ok() && !interrupted()) {
    R.budget.active = true;
    R.budget.budget_seconds = 60 * o.budget_minutes;
    if (R.plan.from_scenes) {
      R.budget.choice = "the levels are the given scene files: the budget cannot choose them (prediction only)";
    } else {
      const double left = R.budget.budget_seconds - R.levels[0].child.wall_seconds;
      R.plan = choose_budget_plan(o, R.levels[0], m, left, n_variants, R.budget, R.ablation_level);
      if (o.ablate.empty()) R.ablation_level = -1;
    }
  }
  for (const auto& l : R.plan.levels) R.predicted.push_back(predict_cost(m, l));
  if (!R.predicted.empty() && resolved_scene_json(R.plan.levels[0]) == resolved_scene_json(R.levels[0].spec)) {
    R.predicted[0] = {};  // level 0 is measured, not predicted
  } else {
    R.levels.clear();  // the plan's coarsest level differs (dx refinement with another finest step): run it
  }

  for (std::size_t k = R.levels.size(); k < R.plan.levels.size() && !interrupted(); ++k) {
    R.levels.push_back(runner.run(R.plan.levels[k], "L" + std::to_string(k), level_dir(int(k)), &R.predicted[k]));
  }

  // quantities over the levels that ran (an interrupted study analyses what it has)
  const double t_end = R.plan.levels.back().t_end;
  R.windows = o.windows.empty() ? std::vector<Window>{{0.0, t_end}} : o.windows;
  AnalysisInput in;
  for (std::size_t k = 0; k < R.levels.size(); ++k) {
    in.levels.push_back(&R.levels[k]);
    in.refined.push_back(R.plan.levels[k].refined);
  }
  in.formal_order = R.plan.formal_order;
  in.windows = R.windows;
  in.norm = R.norm;
  R.quantities = analyse(in);
  {
    std::string edge;
    for (const auto& q : R.quantities)
      if (q.kind == Kind::Mean) {
        bool has_peak = false;
        for (const auto& p : R.quantities) has_peak = has_peak || (p.kind == Kind::Peak && p.series == q.series &&
                                                                   p.window.label() == q.window.label());
        if (!has_peak) edge += (edge.empty() ? "" : ", ") + q.series + " [" + q.window.label() + "]";
      }
    if (!edge.empty())
      R.notes.push_back("no peak quantities for " + edge + ": the largest magnitude lies at the window's start or "
                        "end in every level (no peak event; the end or start value stands for it)");
  }
  geometry_notes(R);
  for (const auto& l : R.levels)
    if (!l.ok())
      R.notes.push_back("level " + l.dir.filename().string() + " exited " + std::to_string(l.child.exit_code) + ": " +
                        l.message);

  // ablation at the chosen level, against that level's own run
  if (!o.ablate.empty() && R.ablation_level >= 0 && std::size_t(R.ablation_level) < R.levels.size() &&
      R.levels[std::size_t(R.ablation_level)].ok()) {
    const auto& base = R.levels[std::size_t(R.ablation_level)];
    int k = 0;
    for (const auto& v : variants) {
      if (interrupted()) break;
      const LevelSpec spec = variant_level(base.spec, v.sets);
      const std::string name = "A" + std::to_string(k++) + "_" + safe_name(v.label);
      R.ablation_predicted.push_back(predict_cost(m, spec));
      AblationResult a;
      a.variant = v;
      a.run = runner.run(spec, name, R.dir / "ablation" / name, &R.ablation_predicted.back());
      judge_ablation(a, base, R.quantities, std::size_t(R.ablation_level), R.norm);
      runner.say("%s: %s (%s)\n", v.label.c_str(), a.verdict.c_str(), a.reason.c_str());
      R.ablations.push_back(std::move(a));
    }
  } else if (!o.ablate.empty()) {
    R.notes.push_back("no ablation was run: no finished level to ablate (or the budget left no room for it)");
  }

  const double d = R.plan.levels[0].dimension;
  const double cost_exp = R.plan.refine == Refine::Both ? d + 1 : R.plan.refine == Refine::Dx ? d : 1.0;
  for (const auto& t : tols) R.tolerances.push_back(evaluate_tolerance(t, R.quantities, in.refined, cost_exp));

  // predicted (after the coarsest level) against actual, over every run of the study
  for (std::size_t k = 0; k < R.levels.size(); ++k) {
    R.budget.actual_wall += R.levels[k].child.wall_seconds;
    R.budget.actual_cpu += R.levels[k].child.cpu_seconds;
    const bool measured = k == 0 && R.predicted[0].wall == 0;
    R.budget.predicted_wall += measured ? R.levels[k].child.wall_seconds : R.predicted[k].wall;
    R.budget.predicted_cpu += measured ? R.levels[k].child.cpu_seconds : R.predicted[k].cpu;
  }
  for (std::size_t k = 0; k < R.ablations.size(); ++k) {
    R.budget.actual_wall += R.ablations[k].run.child.wall_seconds;
    R.budget.actual_cpu += R.ablations[k].run.child.cpu_seconds;
    R.budget.predicted_wall += R.ablation_predicted[k].wall;
    R.budget.predicted_cpu += R.ablation_predicted[k].cpu;
  }

  R.exit_code = 0;
  for (const auto& l : R.levels)
    if (l.child.exit_code == 3) R.exit_code = 3;
  if (const int sig = interrupt_signal()) {
    R.exit_code = sig == SIGINT ? 130 : 143;
    R.notes.push_back("the study was interrupted: the report covers the runs that finished");
  }
  R.finished = iso_now();
  R.load_end = load_now();
  R.study_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  write_study_outputs(R);
  R.plots = o.plots ? make_plots(R) : "not made (--no-plots)";
  write_report(R);  // again, with what became of the plots
  if (!o.quiet) print_summary(R);
  return R.exit_code;
}

}  // namespace varsph::study
