#include "study/ablation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/errors.hpp"
#include "scene/json_reader.hpp"
#include "scene/scene.hpp"

namespace varsph::study {
namespace {

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

const std::vector<std::string> kBoundaryModels = {"repulsive", "dynamic", "dummy_adami", "soft_repulsive"};
const std::vector<std::string> kIntegrators = {"verlet", "variational", "symplectic_euler", "predictor_corrector",
                                               "rk4", "verlet_dsph"};

// Whether the base scene runs with the term: the scene names it, or its set-up supplies it (the engineering
// set-up's physics.riemann; issue 35), so that the variant switches it off with KEY=null.
bool present_in_scene(const LevelSpec& base, const scene::Scene& s, const std::string& key) {
  auto root = scene::read_json_file(base.scene);
  for (const auto& o : base.overrides) scene::apply_override(root, o, base.scene.string());
  const auto ptr = scene::pointer_of(key);
  if (root.contains(ptr) && !root.at(ptr).is_null()) return true;
  return std::find(s.setup_supplied.begin(), s.setup_supplied.end(), key) != s.setup_supplied.end();
}

}  // namespace

std::vector<AblationVariant> ablation_variants(const std::vector<std::string>& items, const LevelSpec& base,
                                               std::vector<std::string>& notes) {
  const scene::Scene s = scene::parse_scene(base.scene, base.overrides);
  // c0 and the repulsive wall's D follow gravity and the fluid height when "auto": hold them at the base's
  // values, so a variant changes its term and nothing else
  const std::vector<std::string> pins = {"fluid.c0=" + num(s.c0), "fluid.c0_factor=null",
                                         "fluid.reference_height=null", "fluid.reference_speed=null",
                                         "boundary.repulsive.D=" + num(s.wall_D)};
  std::vector<AblationVariant> out;
  for (const auto& item : items) {
    std::vector<AblationVariant> vs;
    bool alternatives = false;  // one variant per alternative of a model: drop those that cannot run
    const auto eq = item.find('=');
    if (eq != std::string::npos && item.substr(eq + 1) == "null") {
      vs.push_back({item.substr(0, eq), "without " + item.substr(0, eq), {item}});
    } else if (eq != std::string::npos) {
      vs.push_back({item.substr(0, eq), item.substr(0, eq) + " = " + item.substr(eq + 1), {item}, true});
    } else if (item == "gravity") {
      std::string zeros = "[";
      for (int a = 0; a < s.dimension; ++a) zeros += a ? ",0" : "0";
      vs.push_back({item, "without gravity", {"gravity=" + zeros + "]"}});
    } else if (item == "boundary.model") {
      alternatives = true;
      for (const auto& m : kBoundaryModels)
        if (m != s.boundary_model) vs.push_back({item, "boundary.model = " + m, {"boundary.model=" + m}, true});
    } else if (item == "integrator" || item == "integrator.type") {
      alternatives = true;
      for (const auto& m : kIntegrators)
        if (m != s.integrator) vs.push_back({"integrator.type", "integrator.type = " + m, {"integrator.type=" + m}, true});
    } else if (item == "integrator.alpha") {
      if (s.integrator != "variational")
        throw InputError("--ablate integrator.alpha: the scene's integrator is " + s.integrator +
                         " (alpha belongs to the variational integrator); ablate integrator.type=variational, or "
                         "give the alternative as integrator.alpha=VALUE with a variational scene");
      alternatives = true;
      for (double a : {0.25, 0.5, 0.75})
        if (std::abs(a - s.alpha) > 1e-12)
          vs.push_back({item, "integrator.alpha = " + num(a), {"integrator.alpha=" + num(a)}, true});
    } else if (item == "physics.density") {
      const std::string other = s.density == "continuity" ? "summation" : "continuity";
      vs.push_back({item, "physics.density = " + other, {"physics.density=" + other}, true});
    } else if (item.rfind("physics.", 0) == 0 && item.size() > 8) {
      if (present_in_scene(base, s, item)) vs.push_back({item, "without " + item, {item + "=null"}});
      else vs.push_back({item, "with " + item + " (its defaults)", {item + "={}"}});
    } else {
      throw InputError("--ablate " + item + ": expected a physics.* term, gravity, boundary.model, integrator.type, "
                       "integrator.alpha, physics.density, or KEY=VALUE for one alternative (e.g. "
                       "boundary.model=dynamic)");
    }
    for (auto& v : vs) {
      std::vector<std::string> sets = pins;
      sets.insert(sets.end(), v.sets.begin(), v.sets.end());
      try {
        validate_level(variant_level(base, sets));  // an impossible variant stops here, before any run
      } catch (const InputError& e) {
        if (alternatives) {
          notes.push_back("--ablate " + item + ": " + v.label + " skipped (this scene cannot use it: " + e.what() + ")");
          continue;
        }
        throw InputError("--ablate " + item + ": the variant \"" + v.label + "\" is not a valid scene: " + e.what());
      }
      v.sets = sets;
      out.push_back(v);
    }
  }
  return out;
}

void judge_ablation(AblationResult& a, const LevelRun& base, const std::vector<Quantity>& quantities,
                    std::size_t level, Norm norm) {
  a.effects.clear();
  if (base.child.cpu_seconds > 0) a.cpu_saving = (base.child.cpu_seconds - a.run.child.cpu_seconds) / base.child.cpu_seconds;
  if (base.child.wall_seconds > 0)
    a.wall_saving = (base.child.wall_seconds - a.run.child.wall_seconds) / base.child.wall_seconds;
  if (!a.run.ok()) {
    const std::string why = a.run.message.empty() ? "see its log" : a.run.message;
    if (a.run.child.exit_code == 3) {
      a.verdict = a.variant.alternative ? "fails" : "essential";
      a.reason = std::string(a.variant.alternative ? "the run fails with it" : "the run fails without it") +
                 " (exit 3: " + why + ")";
    } else {
      a.verdict = "failed";
      a.reason = "the variant's run exited " + std::to_string(a.run.child.exit_code) + ": " + why;
    }
    return;
  }
  double worst = -1;
  const TermEffect* decide = nullptr;
  for (const auto& q : quantities) {
    const Series sb = run_series(base, q.series), sv = run_series(a.run, q.series);
    if (sb.empty() || sv.empty()) continue;
    TermEffect e;
    e.quantity = q.name;
    e.effect = quantity_difference(sb, sv, q.kind, q.window, norm);
    e.error = level < q.est.error.size() ? q.est.error[level] : std::numeric_limits<double>::quiet_NaN();
    if (!std::isfinite(e.effect)) continue;
    // a difference at the rounding floor is no effect, whatever the (equally rounding-sized) error it meets
    e.ratio = (e.effect <= q.noise || (q.rounding_only && q.kind == Kind::PeakTime)) ? 0.0
              : e.error > 0      ? e.effect / e.error
                                 : std::numeric_limits<double>::infinity();
    if (!std::isfinite(e.error)) e.ratio = std::numeric_limits<double>::quiet_NaN();
    a.effects.push_back(e);
  }
  for (const auto& e : a.effects)
    if (std::isfinite(e.error) && e.ratio > worst) {
      worst = e.ratio;
      decide = &e;
    }
  if (!decide) {
    a.verdict = "no estimate";
    a.reason = "no quantity has a discretisation error estimate at this level (run at least two levels)";
    return;
  }
  char buf[400];
  std::snprintf(buf, sizeof buf, "largest effect relative to the discretisation error: %s (effect %.3g, error %.3g, "
                "ratio %.3g)", decide->quantity.c_str(), decide->effect, decide->error, decide->ratio);
  a.reason = buf;
  if (a.variant.alternative)
    a.verdict = worst < 1 ? "no difference beyond the discretisation error" : worst >= 10 ? "differs strongly" : "differs";
  else
    a.verdict = worst < 1 ? "not needed at this resolution" : worst >= 10 ? "essential" : "needed";
}

}  // namespace varsph::study
