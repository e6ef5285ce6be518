#include "study/study_report.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "io/atomic_file.hpp"
#include "study/child_process.hpp"

namespace varsph::study {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string g(double v, int prec = 4) {
  if (!std::isfinite(v)) return std::isinf(v) ? (v > 0 ? "inf" : "-inf") : "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

std::string pct(double v) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, v < 1e-3 ? "%.2g %%" : "%.3g %%", 100 * v);
  return buf;
}

std::string csv_quote(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string o = "\"";
  for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string o;
  for (const auto& s : v) o += (o.empty() ? "" : sep) + s;
  return o;
}

std::string dt_text(const LevelSpec& l) { return l.dt ? g(*l.dt, 4) : "CFL " + g(l.cfl ? *l.cfl : 0, 3); }

json level_json(const LevelRun& l, const Prediction* p) {
  json j = {{"dir", l.dir.string()},
            {"scene", l.spec.scene.string()},
            {"level_sets", l.spec.level_sets},
            {"overrides", l.spec.overrides},
            {"dx", l.spec.dx},
            {"h", l.spec.h},
            {"dt", l.spec.dt ? json(*l.spec.dt) : json(nullptr)},
            {"cfl", l.spec.cfl ? json(*l.spec.cfl) : json(nullptr)},
            {"dt_estimate", l.spec.dt_estimate},
            {"refined", l.spec.refined},
            {"fluid_particles", l.spec.fluid},
            {"boundary_particles", l.spec.boundary},
            {"fluid_mass", l.spec.fluid_mass},
            {"t_end", l.spec.t_end},
            {"status", l.status},
            {"exit_code", l.child.exit_code},
            {"message", l.message},
            {"reused", l.reused},
            {"steps", l.steps},
            {"particle_steps", l.particle_steps()},
            {"wall_seconds", l.child.wall_seconds},
            {"solver_wall_seconds", l.solver_wall},
            {"cpu_seconds", l.child.cpu_seconds},
            {"peak_rss_mb", l.child.peak_rss_mb},
            {"load_before", l.child.load_before},
            {"load_after", l.child.load_after}};
  if (p && p->wall > 0)
    j["predicted"] = {{"steps", p->steps},
                      {"particle_steps", p->particle_steps},
                      {"wall_seconds", p->wall},
                      {"cpu_seconds", p->cpu},
                      {"peak_rss_mb", p->rss_mb}};
  return j;
}

json quantity_json(const Quantity& q) {
  std::vector<double> rel;
  for (double b : q.est.bound) rel.push_back(q.relative(b));
  return {{"name", q.name},
          {"series", q.series},
          {"kind", q.kind == Kind::Series ? "series" : to_string(q.kind)},
          {"window", {q.window.t0, q.window.t1}},
          {"values", q.values},
          {"error_estimate", q.est.error},
          {"error_bound", q.est.bound},
          {"relative_error_bound", rel},
          {"scale", q.scale},
          {"order", q.est.order},
          {"order_used", q.est.order_used},
          {"order_fit", q.est.order_fit},
          {"orders_of_triples", q.est.orders},
          {"extrapolated", q.est.extrapolated},
          {"safety_factor", q.est.safety},
          {"trusted", q.est.trusted()},
          {"flags", q.est.flags},
          {"notes", q.est.notes}};
}

std::string series_file(const Quantity& q) {
  std::string w = q.window.label();
  for (char& c : w)
    if (c == ':') c = '_';
  return q.series + "__" + w + ".csv";
}

void write_series(const StudyResult& r) {
  for (const auto& q : r.quantities) {
    if (q.kind != Kind::Series || q.grid.empty()) continue;
    std::ostringstream o;
    o << "time";
    for (std::size_t k = 0; k < q.resampled.size(); ++k) o << ",L" << k;
    o << ",extrapolated\n";
    o.precision(12);
    for (std::size_t i = 0; i < q.grid.size(); ++i) {
      o << q.grid[i];
      for (const auto& lv : q.resampled) o << "," << (lv.empty() || !std::isfinite(lv[i]) ? "" : g(lv[i], 12));
      o << "," << (q.extrapolated_series.empty() ? "" : g(q.extrapolated_series[i], 12)) << "\n";
    }
    io::write_text_atomically(r.dir / "series" / series_file(q), o.str());
  }
}

std::string report_text(const StudyResult& r) {
  const auto& p = r.plan;
  std::ostringstream o;
  const std::string name = p.levels.empty() ? "?" : p.levels[0].name;
  o << "# Study of `" << name << "` (`varsph study`)\n\n";
  o << "Command: `" << join(r.options.command_line, " ") << "`  \n";
  o << "Started " << r.started << ", finished " << r.finished << "; study wall time " << g(r.study_wall, 4)
    << " s; 1-minute load average " << g(r.load_start, 3) << " at the start, " << g(r.load_end, 3)
    << " at the end (wall times on a shared machine vary with the load; CPU seconds much less).\n\n";
  o << "Refinement: **" << to_string(p.refine) << "**"
    << (p.refine == Refine::Both  ? " (particle spacing with h/dx fixed, time step with it: the scene's CFL number)"
        : p.refine == Refine::Dx  ? " (particle spacing with h/dx fixed; every level at the finest level's step)"
                                  : " (time step only, particle spacing fixed)")
    << ", " << (p.from_scenes ? "levels given as scene files" : "ratio " + g(p.ratio, 4)) << ", " << p.levels.size()
    << " levels. Formal order " << g(p.formal_order, 3) << ": " << p.formal_order_why
    << ". Series compared in the " << to_string(r.norm) << " norm on a common time base (linear interpolation onto "
    << "a uniform grid at the coarsest sampling interval).\n\n";
  o << "What the errors below are: the distance of each level from the converged solution *of this model* (its "
       "c0, physics terms, wall model"
    << (p.refine != Refine::Dt ? ", and its h/dx" : "")
    << "), estimated from the levels alone. Model error is not in them";
  if (p.refine != Refine::Dt)
    o << "; nor is the part of the particle-approximation error that depends on dx/h (Quinlan et al. 2006), which "
         "does not shrink when dx and h are refined together: check it with `--ablate kernel.h_over_dx=X` at a "
         "larger X (docs/study.md shows it at 1 % on Poiseuille start-up)";
  o << ".\n\n";

  o << "## Levels and their cost\n\n";
  o << "| level | dx [m] | dt [s] | fluid | boundary | fluid mass | steps | particle-steps | wall [s] (predicted) | "
       "CPU [s] (predicted) | peak memory [MB] (predicted) | load | exit |\n";
  o << "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < r.levels.size(); ++k) {
    const auto& l = r.levels[k];
    const Prediction* pr = k < r.predicted.size() && r.predicted[k].wall > 0 ? &r.predicted[k] : nullptr;
    o << "| L" << k << " | " << g(l.spec.dx) << " | " << dt_text(l.spec) << " | " << l.spec.fluid << " | "
      << l.spec.boundary << " | " << g(l.spec.fluid_mass, 6) << " | " << l.steps << " | " << g(l.particle_steps(), 4)
      << " | " << g(l.child.wall_seconds, 4) << (pr ? " (" + g(pr->wall, 3) + ")" : std::string(" (measured)"))
      << " | " << g(l.child.cpu_seconds, 4) << (pr ? " (" + g(pr->cpu, 3) + ")" : std::string()) << " | "
      << g(l.child.peak_rss_mb, 4) << (pr ? " (" + g(pr->rss_mb, 3) + ")" : std::string()) << " | "
      << g(l.child.load_before, 2) << "-" << g(l.child.load_after, 2) << " | " << l.child.exit_code
      << (l.reused ? " (reused)" : "") << " |\n";
  }
  o << "\nPredictions come from the coarsest level's seconds per fluid particle-step (wall and CPU) and its "
       "resident memory per particle; predicted total for the study "
    << g(r.budget.predicted_wall, 4) << " s wall / " << g(r.budget.predicted_cpu, 4) << " s CPU, actual "
    << g(r.budget.actual_wall, 4) << " s / " << g(r.budget.actual_cpu, 4) << " s";
  if (r.budget.actual_cpu > 0)
    o << " (CPU prediction off by " << g(100 * (r.budget.predicted_cpu / r.budget.actual_cpu - 1), 3) << " %)";
  o << ".\n\n";
  if (r.budget.active) {
    o << "**Budget** " << g(r.budget.budget_seconds / 60, 4) << " min: " << r.budget.choice << ".";
    if (!r.budget.rejected.empty()) o << " Not chosen: " << join(r.budget.rejected, "; ") << ".";
    o << " The whole study took " << g(r.study_wall, 4) << " s of wall time.\n\n";
  }

  o << "## Quantities: value at each level, estimated error, observed order\n\n";
  o << "Each cell: the level's value and, in brackets, its defended error (safety factor x the Richardson "
       "estimate) relative to the quantity's scale. Trusted estimates use a safety factor 1.25; flagged ones 3 "
       "and the reasons listed below the table.\n\n";
  o << "| quantity |";
  for (std::size_t k = 0; k < r.levels.size(); ++k) o << " L" << k << " |";
  o << " extrapolated | order (used) | trusted |\n|---|";
  for (std::size_t k = 0; k < r.levels.size(); ++k) o << "---|";
  o << "---|---|---|\n";
  int flag_no = 0;
  std::ostringstream flags;
  for (const auto& q : r.quantities) {
    o << "| `" << q.name << "` |";
    for (std::size_t k = 0; k < r.levels.size(); ++k)
      o << " " << g(k < q.values.size() ? q.values[k] : NAN, 5) << " ("
        << pct(k < q.est.bound.size() ? q.relative(q.est.bound[k]) : NAN) << ") |";
    o << " " << g(q.est.extrapolated, 6) << " | " << g(q.est.order, 3) << " (" << g(q.est.order_used, 3) << ") | ";
    if (q.est.trusted()) {
      o << "yes |\n";
    } else {
      ++flag_no;
      o << "no [" << flag_no << "] |\n";
      flags << flag_no << ". `" << q.name << "`: " << join(q.est.flags, "; ") << ".\n";
    }
  }
  if (flag_no) o << "\nWhy an estimate is not trusted:\n\n" << flags.str();
  if (!r.notes.empty()) {
    o << "\n## Notes\n\n";
    for (const auto& n : r.notes) o << "* " << n << "\n";
  }

  if (!r.tolerances.empty()) {
    o << "\n## Speed against error: the cheapest level that meets each tolerance\n\n";
    for (const auto& t : r.tolerances) {
      o << "**`" << t.spec.text << "`** (" << (t.spec.relative ? pct(t.spec.value) + " of each quantity's scale"
                                                               : g(t.spec.value) + " in the quantity's unit")
        << ", on the defended error): ";
      if (t.cheapest_level >= 0) {
        const auto& l = r.levels[std::size_t(t.cheapest_level)];
        o << "level L" << t.cheapest_level << " (" << l.spec.label() << ", " << g(l.child.wall_seconds, 3)
          << " s wall, " << g(l.child.cpu_seconds, 3) << " s CPU) meets it for all " << t.quantities.size() - t.without_estimate
          << " matched quantities with an estimate.";
      } else {
        o << "no level meets it for every matched quantity.";
      }
      if (t.without_estimate) o << " " << t.without_estimate << " matched quantities have no estimate.";
      o << "\n\n";
      std::size_t shown = 0;
      for (const auto& v : t.quantities) {
        if (v.cheapest_level >= 0 || shown >= 12) continue;
        if (shown++ == 0) o << "| quantity not met | tolerance | predicted dx/dt to meet it | cost x the finest |\n|---|---|---|---|\n";
        if (v.needed_refined > 0)
          o << "| `" << v.quantity << "` | " << g(v.tolerance) << " | " << g(v.needed_refined) << " | "
            << g(v.needed_cost_factor, 3) << " |\n";
        else
          o << "| `" << v.quantity << "` | " << g(v.tolerance) << " | not predictable (flagged estimate: refine "
            "and run again) | - |\n";
      }
      if (shown) o << "\n";
    }
  }

  if (!r.ablations.empty() || !r.options.ablate.empty()) {
    o << "\n## Ablation: what the scene needs\n\n";
    if (r.ablation_level >= 0 && std::size_t(r.ablation_level) < r.levels.size())
      o << "At level L" << r.ablation_level << " (" << r.levels[std::size_t(r.ablation_level)].spec.label()
        << "): each variant against the same level with the term, on every quantity; a term is **not needed at "
           "this resolution** when every effect is below the level's estimated discretisation error, "
           "**essential** when an effect exceeds 10x it or the run fails without it.\n\n";
    o << "| variant | verdict | decided by | CPU saving | wall saving |\n|---|---|---|---|---|\n";
    for (const auto& a : r.ablations)
      o << "| " << a.variant.label << " | **" << a.verdict << "** | " << a.reason << " | " << pct(a.cpu_saving)
        << " | " << pct(a.wall_saving) << " |\n";
  }

  o << "\n## Files\n\n`study.json` (everything), `study.csv` (a row per quantity and level, cost beside error), "
       "`levels.csv`, `series/` (each series of every level on the common time base and the extrapolated "
       "series), `levels/L*/` and `ablation/*/` (run directories: open them side by side with "
       "`pvpython paraview/study_levels.py " << r.dir.string() << "`), `logs/`. Plots: " << r.plots << "\n";
  return o.str();
}

}  // namespace

void write_report(const StudyResult& r) { io::write_text_atomically(r.dir / "report.md", report_text(r)); }

void write_study_outputs(const StudyResult& r) {
  json j;
  j["program"] = "varsph study";
  j["version"] = VARSPH_VERSION;
  j["command_line"] = r.options.command_line;
  j["started"] = r.started;
  j["finished"] = r.finished;
  j["study_wall_seconds"] = r.study_wall;
  j["load_average"] = {{"start", r.load_start}, {"end", r.load_end}};
  j["exit_code"] = r.exit_code;
  j["refine"] = to_string(r.plan.refine);
  j["ratio"] = r.plan.ratio;
  j["from_scenes"] = r.plan.from_scenes;
  j["formal_order"] = r.plan.formal_order;
  j["formal_order_why"] = r.plan.formal_order_why;
  j["norm"] = to_string(r.norm);
  j["windows"] = json::array();
  for (const auto& w : r.windows) j["windows"].push_back({w.t0, w.t1});
  j["levels"] = json::array();
  for (std::size_t k = 0; k < r.levels.size(); ++k)
    j["levels"].push_back(level_json(r.levels[k], k < r.predicted.size() ? &r.predicted[k] : nullptr));
  j["budget"] = {{"active", r.budget.active},
                 {"budget_seconds", r.budget.budget_seconds},
                 {"choice", r.budget.choice},
                 {"rejected", r.budget.rejected},
                 {"predicted_wall_seconds", r.budget.predicted_wall},
                 {"predicted_cpu_seconds", r.budget.predicted_cpu},
                 {"actual_wall_seconds", r.budget.actual_wall},
                 {"actual_cpu_seconds", r.budget.actual_cpu}};
  j["quantities"] = json::array();
  for (const auto& q : r.quantities) j["quantities"].push_back(quantity_json(q));
  json ab = {{"level", r.ablation_level}, {"variants", json::array()}};
  for (std::size_t k = 0; k < r.ablations.size(); ++k) {
    const auto& a = r.ablations[k];
    json v = {{"term", a.variant.term},
              {"label", a.variant.label},
              {"sets", a.variant.sets},
              {"verdict", a.verdict},
              {"reason", a.reason},
              {"cpu_saving", a.cpu_saving},
              {"wall_saving", a.wall_saving},
              {"run", level_json(a.run, k < r.ablation_predicted.size() ? &r.ablation_predicted[k] : nullptr)},
              {"effects", json::array()}};
    for (const auto& e : a.effects)
      v["effects"].push_back({{"quantity", e.quantity}, {"effect", e.effect}, {"error", e.error}, {"ratio", e.ratio}});
    ab["variants"].push_back(v);
  }
  j["ablation"] = ab;
  j["tolerances"] = json::array();
  for (const auto& t : r.tolerances) {
    json tj = {{"text", t.spec.text},       {"pattern", t.spec.pattern},         {"value", t.spec.value},
               {"relative", t.spec.relative}, {"cheapest_level", t.cheapest_level},
               {"without_estimate", t.without_estimate}, {"quantities", json::array()}};
    for (const auto& v : t.quantities)
      tj["quantities"].push_back({{"quantity", v.quantity},
                                  {"tolerance", v.tolerance},
                                  {"cheapest_level", v.cheapest_level},
                                  {"needed_refined", v.needed_refined},
                                  {"needed_cost_factor", v.needed_cost_factor}});
    j["tolerances"].push_back(tj);
  }
  j["notes"] = r.notes;
  io::write_text_atomically(r.dir / "study.json", j.dump(1) + "\n");

  std::ostringstream c;
  c << "quantity,series,kind,window_start,window_end,level,refined,dx,dt,fluid_particles,particle_steps,"
       "wall_seconds,cpu_seconds,peak_rss_mb,value,error_estimate,error_bound,relative_error_bound,extrapolated,"
       "order,order_used,trusted,flags\n";
  for (const auto& q : r.quantities)
    for (std::size_t k = 0; k < r.levels.size(); ++k) {
      const auto& l = r.levels[k];
      c << csv_quote(q.name) << "," << q.series << "," << (q.kind == Kind::Series ? "series" : to_string(q.kind))
        << "," << g(q.window.t0, 12) << "," << g(q.window.t1, 12) << "," << k << "," << g(l.spec.refined, 12) << ","
        << g(l.spec.dx, 12) << "," << g(l.spec.dt_estimate, 12) << "," << l.spec.fluid << ","
        << g(l.particle_steps(), 12) << "," << g(l.child.wall_seconds, 6) << "," << g(l.child.cpu_seconds, 6) << ","
        << g(l.child.peak_rss_mb, 6) << "," << g(q.values[k], 12) << "," << g(q.est.error[k], 6) << ","
        << g(q.est.bound[k], 6) << "," << g(q.relative(q.est.bound[k]), 6) << "," << g(q.est.extrapolated, 12) << ","
        << g(q.est.order, 4) << "," << g(q.est.order_used, 4) << "," << (q.est.trusted() ? 1 : 0) << ","
        << csv_quote(join(q.est.flags, " | ")) << "\n";
    }
  io::write_text_atomically(r.dir / "study.csv", c.str());

  std::ostringstream lv;
  lv << "level,dx,dt,refined,fluid_particles,boundary_particles,fluid_mass,steps,particle_steps,exit_code,"
        "wall_seconds,cpu_seconds,peak_rss_mb,predicted_wall_seconds,predicted_cpu_seconds,predicted_peak_rss_mb,"
        "load_before,load_after,reused\n";
  for (std::size_t k = 0; k < r.levels.size(); ++k) {
    const auto& l = r.levels[k];
    const Prediction pr = k < r.predicted.size() ? r.predicted[k] : Prediction{};
    lv << k << "," << g(l.spec.dx, 12) << "," << g(l.spec.dt_estimate, 12) << "," << g(l.spec.refined, 12) << ","
       << l.spec.fluid << "," << l.spec.boundary << "," << g(l.spec.fluid_mass, 12) << "," << l.steps << ","
       << g(l.particle_steps(), 12) << "," << l.child.exit_code << "," << g(l.child.wall_seconds, 6) << ","
       << g(l.child.cpu_seconds, 6) << "," << g(l.child.peak_rss_mb, 6) << ","
       << (pr.wall > 0 ? g(pr.wall, 6) : "") << "," << (pr.wall > 0 ? g(pr.cpu, 6) : "") << ","
       << (pr.wall > 0 ? g(pr.rss_mb, 6) : "") << "," << g(l.child.load_before, 3) << "," << g(l.child.load_after, 3)
       << "," << (l.reused ? 1 : 0) << "\n";
  }
  io::write_text_atomically(r.dir / "levels.csv", lv.str());
  write_series(r);
  write_report(r);
}

std::string make_plots(const StudyResult& r) {
  const auto exists = [](const fs::path& p) {
    std::error_code ec;
    return !p.empty() && fs::exists(p, ec);
  };
  fs::path script;
  if (const char* e = std::getenv("VARSPH_STUDY_PLOT")) script = e;
  if (!exists(script)) {
    std::error_code ec;
    const auto exe = fs::read_symlink("/proc/self/exe", ec);
    script = exe.parent_path().parent_path() / "share" / "varsph" / "study" / "plot_study.py";
  }
#ifdef VARSPH_STUDY_PLOT_SCRIPT
  if (!exists(script)) script = VARSPH_STUDY_PLOT_SCRIPT;
#endif
  if (!exists(script)) return "not made: plot_study.py not found (set VARSPH_STUDY_PLOT to its path)";
  fs::path python;
  if (const char* e = std::getenv("VARSPH_PYTHON")) python = e;
  if (!exists(python)) python = "/usr/bin/python3";
  if (!exists(python)) return "not made: no Python found (set VARSPH_PYTHON to a python3 with matplotlib)";
  const fs::path log = r.dir / "logs" / "plots.log";
  std::error_code ec;
  fs::remove(log, ec);
  const auto c = run_child({python.string(), script.string(), r.dir.string()}, log);
  if (c.exit_code == 0) return "`plots/*.png`, made by `" + script.string() + "` with " + python.string() + ".";
  if (c.exit_code == 77) return "not made: " + python.string() + " has no matplotlib (see logs/plots.log).";
  return "not made: the plot script exited " + std::to_string(c.exit_code) + " (see logs/plots.log).";
}

void print_summary(const StudyResult& r) {
  std::printf("varsph study: %zu level(s), %zu quantities", r.levels.size(), r.quantities.size());
  std::size_t trusted = 0;
  for (const auto& q : r.quantities) trusted += q.est.trusted();
  std::printf(" (%zu with a trusted estimate); predicted %.3g s CPU, actual %.3g s; study %.3g s wall\n", trusted,
              r.budget.predicted_cpu, r.budget.actual_cpu, r.study_wall);
  for (const auto& t : r.tolerances)
    std::printf("varsph study: tolerance %s: %s\n", t.spec.text.c_str(),
                t.cheapest_level >= 0 ? ("level L" + std::to_string(t.cheapest_level) + " is the cheapest that meets it").c_str()
                                      : "no level meets it for every matched quantity");
  for (const auto& a : r.ablations)
    std::printf("varsph study: %s: %s\n", a.variant.label.c_str(), a.verdict.c_str());
  std::printf("varsph study: report %s; plots %s\n", (r.dir / "report.md").string().c_str(), r.plots.c_str());
}

}  // namespace varsph::study
