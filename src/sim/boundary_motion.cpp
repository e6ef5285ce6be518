#include "sim/boundary_motion.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/errors.hpp"
#include "scene/key_suggest.hpp"
#include "scene/scene.hpp"
#include "physics/pair_loop.hpp"
#include "waves/wave_theory.hpp"

namespace varsph {
namespace {

using nlohmann::json;

template <int D>
Vec<D> vec_of(const json& j, const std::string& where, const std::string& key) {
  if (!j.contains(key) || !j[key].is_array() || j[key].size() != std::size_t(D))
    throw InputError(where + "." + key + ": expected an array of " + std::to_string(D) + " numbers");
  Vec<D> v;
  for (int a = 0; a < D; ++a) {
    if (!j[key][std::size_t(a)].is_number())
      throw InputError(where + "." + key + ": expected numbers, got " + j[key].dump());
    v[a] = Real(j[key][std::size_t(a)].get<double>());
  }
  return v;
}

double number_of(const json& j, const std::string& where, const std::string& key, double def, bool required = false) {
  if (!j.contains(key)) {
    if (required) throw InputError(where + "." + key + ": expected a number (required)");
    return def;
  }
  if (!j[key].is_number()) throw InputError(where + "." + key + ": expected a number, got " + j[key].dump());
  return j[key].get<double>();
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// Wavemaker laws (docs/waves.md): the paddle signal from wave theory or a file, checked against the
// breaking limits, the flume's water and the domain before the run starts (exit 2 naming the key).
template <int D>
void parse_wavemaker(const json& m, const std::string& where, const scene::Scene* sc, std::size_t body,
                     MotionLaw<D>& law) {
  const bool flap = law.type == MotionLaw<D>::Type::Flap;
  const std::string kind = flap ? "flap" : "piston";
  if (!sc) throw InputError(where + ": a " + kind + " wavemaker needs the scene");
  constexpr int V = D - 1;  // vertical axis
  // still water: the fluid box bodies' bed and the top of the particle rows they hold (a box holds
  // floor(height / dx) rows, as sim/build_particles.cpp samples it: its water is that deep, not the box)
  double bed = 1e300, top = -1e300;
  double fluid_far = -1e300;  // far end of the water along x
  for (const auto& b : sc->bodies)
    if (b.kind == "fluid" && b.shape == "box" && b.min.size() == std::size_t(D)) {
      const double rows = std::floor((b.max[V] - b.min[V]) / sc->spacing + 1e-6);
      bed = std::min(bed, b.min[V]);
      top = std::max(top, b.min[V] + rows * sc->spacing);
      fluid_far = std::max(fluid_far, b.max[0]);
    }
  const bool have_water = top > bed;
  double depth = number_of(m, where, "depth", have_water ? top - bed : 0.0, !have_water);
  if (!(depth > 0)) throw InputError(where + ".depth: expected a positive still-water depth [m]");
  if (have_water && std::abs(depth - (top - bed)) > 0.5 * sc->spacing)
    throw InputError(where + ".depth: " + num(depth) + " m does not match the fluid body's depth " + num(top - bed) +
                     " m (bed " + num(bed) + ", surface " + num(top) + "; limit: half a spacing, " +
                     num(0.5 * sc->spacing) + " m)");
  if (!have_water) bed = 0;
  double g = 0;
  for (int a = 0; a < D && a < int(sc->gravity.size()); ++a)
    if (a != V && sc->gravity[std::size_t(a)] != 0)
      throw InputError(where + ": a wavemaker needs gravity along -" + std::string(D == 2 ? "y" : "z") + " only");
  if (int(sc->gravity.size()) > V) g = -sc->gravity[std::size_t(V)];
  if (!(g > 0)) throw InputError(where + ": a wavemaker needs gravity (along -" + std::string(D == 2 ? "y" : "z") + ")");

  waves::PaddleGeometry geo{.flap = flap, .depth = depth, .hinge_height = 0, .g = g};
  if (flap) {
    law.center = vec_of<D>(m, where, "hinge");
    geo.hinge_height = double(law.center[V]) - bed;
    if (!(geo.hinge_height < depth))
      throw InputError(where + ".hinge: the hinge (" + num(geo.hinge_height) + " m above the bed) must lie below the "
                       "still-water level (" + num(depth) + " m)");
    law.arm = depth - geo.hinge_height;
  } else if (m.contains("hinge")) {
    throw InputError(where + ": unknown key 'hinge' for a piston motion (a flap's key)");
  }

  const std::string waves_kind = m.contains("waves") ? (m["waves"].is_string() ? m["waves"].get<std::string>() : "?")
                                                     : "regular";
  // the breaking limits of a wave of height H and period T (McCowan's H/h, Miche's steepness)
  auto check_breaking = [&](double H, double T, const std::string& hkey) {
    const double k = waves::wave_number(2 * std::numbers::pi / T, depth, g), L = 2 * std::numbers::pi / k;
    if (H / depth > waves::kDepthBreakingLimit)
      throw InputError(where + "." + hkey + ": H/h = " + num(H / depth) + " breaks at the paddle (limit " +
                       num(waves::kDepthBreakingLimit) + ", McCowan)");
    if (H / L > waves::miche_limit(k * depth))
      throw InputError(where + "." + hkey + ": the steepness H/L = " + num(H / L) + " breaks (Miche limit 0.142 tanh kh = " +
                       num(waves::miche_limit(k * depth)) + " at kh = " + num(k * depth) + ")");
  };
  auto positive = [&](const std::string& key, double def, bool required) {
    const double v = number_of(m, where, key, def, required);
    if (!(v > 0)) throw InputError(where + "." + key + ": expected a positive number");
    return v;
  };
  auto spectrum = [&]() {
    waves::SpectrumSpec s;
    s.Hs = positive("hs", 0, true);
    s.Tp = positive("tp", 0, true);
    s.gamma = number_of(m, where, "gamma", 3.3);
    if (!(s.gamma >= 1 && s.gamma <= 20)) throw InputError(where + ".gamma: expected a number in [1, 20]");
    const double nc = number_of(m, where, "components", 256);
    if (!(nc >= 1 && nc <= 1e5 && nc == std::floor(nc))) throw InputError(where + ".components: expected an integer in [1, 1e5]");
    s.components = int(nc);
    s.f_min = number_of(m, where, "f_min", 0.5 / s.Tp);
    s.f_max = number_of(m, where, "f_max", 3 / s.Tp);
    if (!(s.f_min > 0 && s.f_max > s.f_min)) throw InputError(where + ".f_max: expected 0 < f_min < f_max [Hz]");
    const double seed = number_of(m, where, "seed", 1);
    if (!(seed >= 0 && seed < 9.007e15 && seed == std::floor(seed))) throw InputError(where + ".seed: expected an integer >= 0");
    s.seed = std::uint64_t(seed);
    const double m0 = waves::discrete_m0(s), target = s.Hs * s.Hs / 16;
    if (!(m0 >= 0.5 * target))
      throw InputError(where + ".f_min: the band " + num(s.f_min) + " .. " + num(s.f_max) + " Hz holds " +
                       num(100 * m0 / target) + " % of the spectrum's energy (limit: at least 50 %; fp = " +
                       num(1 / s.Tp) + " Hz)");
    return s;
  };
  double ramp_default = 0;
  std::vector<waves::Component> comps;
  waves::PaddleSignal signal;
  if (waves_kind == "regular") {
    const double H = positive("height", 0, true), T = positive("period", 0, true);
    check_breaking(H, T, "height");
    const double order = number_of(m, where, "order", 1);
    if (order != 1 && order != 2) throw InputError(where + ".order: expected 1 or 2");
    if (order == 2 && flap) throw InputError(where + ".order: Madsen's second-order correction is for a piston (order 1 for a flap)");
    comps = waves::regular_waves(geo, H, T, number_of(m, where, "phase", 0.0), int(order));
    ramp_default = 2 * T;
    signal = waves::PaddleSignal::sines(comps);
  } else if (waves_kind == "irregular") {
    const auto s = spectrum();
    check_breaking(s.Hs, s.Tp, "hs");
    signal = waves::PaddleSignal::sines(waves::irregular_waves(geo, s));
    ramp_default = 2 * s.Tp;
  } else if (waves_kind == "focused") {
    const auto s = spectrum();
    const double A = positive("crest", 0, true);
    check_breaking(2 * A, s.Tp, "crest");
    const double xf = positive("focus_x", 0, true), tf = positive("focus_t", 0, true);
    signal = waves::PaddleSignal::sines(waves::focused_group(geo, s, A, xf, tf));
    ramp_default = 0;  // the group's own envelope starts it quietly; a ramp may still be named
  } else if (waves_kind == "file") {
    if (!m.contains("file") || !m["file"].is_string()) throw InputError(where + ".file: expected a CSV file name (time, value)");
    const auto path = sc->file.parent_path() / m["file"].get<std::string>();
    try {
      signal = waves::PaddleSignal::read_csv(path.string());
    } catch (const std::invalid_argument& e) {
      throw InputError(where + ".file: " + e.what());
    }
    const std::string column = m.contains("column") && m["column"].is_string() ? m["column"].get<std::string>() : "displacement";
    if (column != "displacement" && column != "angle")
      throw InputError(where + ".column: expected \"displacement\" [m] or \"angle\" [rad]");
    if (column == "angle" && !flap) throw InputError(where + ".column: \"angle\" is a flap's signal");
    law.paddle_angle = column == "angle";
    if (law.paddle_angle && !(signal.max_abs() < 1.0))
      throw InputError(where + ".file: the flap's angle reaches " + num(signal.max_abs()) + " rad (limit 1 rad)");
  } else {
    throw InputError(where + ".waves: expected \"regular\", \"irregular\", \"focused\" or \"file\", got " + m["waves"].dump());
  }
  const double ramp = number_of(m, where, "ramp", ramp_default);
  if (!(ramp >= 0)) throw InputError(where + ".ramp: expected a duration >= 0 [s]");
  signal.set_ramp(ramp);
  // the paddle's reach: its largest excursion at the still-water level against the domain and the water
  const double reach = law.paddle_angle ? law.arm * std::tan(signal.max_abs()) : signal.max_abs();
  const auto& pb = sc->bodies[body];
  if (pb.min.size() == std::size_t(D) && pb.max.size() == std::size_t(D)) {
    const double lo = pb.min[0] - reach, hi = pb.max[0] + reach;
    if (lo < sc->domain_min[0] || hi > sc->domain_max[0])
      throw InputError(where + ": the paddle's stroke (" + num(2 * reach) + " m, x from " + num(lo) + " to " + num(hi) +
                       ") leaves the domain [" + num(sc->domain_min[0]) + ", " + num(sc->domain_max[0]) + "]");
    if (have_water && hi >= fluid_far)
      throw InputError(where + ": the paddle's stroke (" + num(2 * reach) + " m) reaches x = " + num(hi) +
                       ", beyond the water's far end " + num(fluid_far));
  }
  // active absorption (AWAS-Zsurf; Altomare et al. 2017 eq. 12): its target is the signal's linear-theory wave
  if (m.contains("awas") && !(m["awas"].is_boolean() && !m["awas"].get<bool>())) {
    const std::string aw = where + ".awas";
    const json a = m["awas"].is_boolean() ? json::object() : m["awas"];
    if (!a.is_object()) throw InputError(aw + ": expected an object (or true) with gauge, start, gain, drift_time");
    for (auto it = a.begin(); it != a.end(); ++it)
      if (it.key() != "gauge" && it.key() != "start" && it.key() != "gain" && it.key() != "drift_time") {
        const auto guess = scene::closest_key(it.key(), {"gauge", "start", "gain", "drift_time"});
        throw InputError(aw + ": unknown key '" + it.key() + "'" + (guess ? " (did you mean '" + *guess + "'?)" : ""));
      }
    // a flap absorbs as a piston does at the still-water level (below: the flap's gain). A flap hinged above the
    // bed cannot absorb a long wave (the water under its hinge has no paddle to move it), so it is refused here
    if (flap && geo.hinge_height > 0.5 * sc->spacing)
      throw InputError(where + ".hinge: active absorption (awas) needs a flap hinged at the bed or below it; the hinge is " +
                       num(geo.hinge_height) + " m above the bed (limit: half a spacing, " + num(0.5 * sc->spacing) + " m)");
    if (waves_kind == "file")
      throw InputError(aw + ": needs a wave-theory signal (\"regular\", \"irregular\" or \"focused\") for its target "
                       "elevation; a paddle file gives none");
    if (pb.min.size() != std::size_t(D) || pb.max.size() != std::size_t(D))
      throw InputError(aw + ": the paddle must be a box body (its face is the box's max x)");
    auto& A = law.awas;
    A.on = true;
    A.face = pb.max[0];
    if (D == 3) A.across = 0.5 * (pb.min[1] + pb.max[1]);
    A.bed = bed;
    A.depth = depth;
    A.ramp = signal.ramp();
    A.gauge = number_of(a, aw, "gauge", 5 * sc->spacing);
    const double support = 2 * sc->h;  // Wendland / cubic spline support radius
    if (!(A.gauge >= support))
      throw InputError(aw + ".gauge: " + num(A.gauge) + " m is within the kernel's support (" + num(support) +
                       " m) of the paddle's face: the gauge would read the wall's deficit (limit: at least 2h)");
    if (have_water && !(A.face + reach + A.gauge + support < fluid_far))
      throw InputError(aw + ".gauge: the gauge at " + num(A.gauge) + " m from the paddle's face leaves the water (far end " +
                       num(fluid_far) + ")");
    A.start = number_of(a, aw, "start", law.start + A.ramp);
    if (!(A.start >= 0)) throw InputError(aw + ".start: expected a time >= 0 [s]");
    A.drift_time = number_of(a, aw, "drift_time", 0.0);
    if (!(A.drift_time >= 0)) throw InputError(aw + ".drift_time: expected a duration >= 0 [s] (0: no drift correction)");
    const std::string gain = a.contains("gain") ? (a["gain"].is_string() ? a["gain"].get<std::string>() : "?") : "shallow";
    // the target: each first-order component q_i = A_i sin(omega_i tau + phi_i) makes eta_i = A_i (H/S)(k_i)
    // cos(omega_i tau + phi_i - k_i x) (Dean & Dalrymple 1991, 6.2); Madsen's second-order term makes no target
    const std::size_t first = waves_kind == "regular" ? 1 : signal.components().size();
    for (std::size_t c = 0; c < first; ++c) {
      const auto& q = signal.components()[c];
      const double k = waves::wave_number(q.omega, depth, g);
      A.target.push_back({q.amplitude * geo.transfer(k), q.omega, q.phase});
      A.k.push_back(k);
    }
    if (gain == "shallow") {
      A.gain = std::sqrt(g / depth);  // Schaffer & Klopman 2000, shallow water; Altomare et al. 2017 eq. 12
      if (flap) {
        // the flap's velocity at the still-water level U makes the depth-averaged velocity U (h/2 - l) / (h - l)
        // (hinge l <= 0 above the bed; the displacement grows linearly from the hinge): matching it to the long
        // reflected wave's sqrt(g/h) eta gives G = sqrt(g/h) (h - l) / (h/2 - l), 2 sqrt(g/h) on the bed. It is the
        // kh -> 0 limit of omega / (H/S) with the flap's transfer function (docs/waves.md, "a flap").
        const double l = std::min(geo.hinge_height, 0.0);
        A.gain *= (depth - l) / (0.5 * depth - l);
      }
    } else if (gain == "linear") {
      // U = omega / (H/S) eta: the paddle velocity at the still-water level that makes a wave eta at frequency omega
      // (its shallow limit is sqrt(g/h) for a piston, sqrt(g/h) (h - l) / (h/2 - l) for a flap), at the regular
      // wave's period or the spectrum's peak
      const double T = waves_kind == "regular" ? number_of(m, where, "period", 1) : number_of(m, where, "tp", 1);
      const double w = 2 * std::numbers::pi / T, k = waves::wave_number(w, depth, g);
      A.gain = w / geo.transfer(k);
    } else {
      throw InputError(aw + ".gain: expected \"shallow\" (sqrt(g/h)) or \"linear\" (omega / (H/S) at the period), got " +
                       a["gain"].dump());
    }
  }
  law.paddle = std::make_shared<const waves::PaddleSignal>(std::move(signal));
}

}  // namespace

template <int D>
MotionLaw<D> parse_motion(const json& m, const std::string& where, const scene::Scene* sc, std::size_t body) {
  MotionLaw<D> law;
  if (m.is_null()) return law;
  if (!m.is_object() || !m.contains("type") || !m["type"].is_string())
    throw InputError(where + ": expected an object with \"type\": \"translation\" | \"rotation\" | \"oscillation\" | "
                     "\"piston\" | \"flap\"");
  const std::string type = m["type"].get<std::string>();
  const std::vector<std::string> wavemaker{"type", "waves", "depth", "height", "period", "phase", "order", "hs", "tp",
                                           "gamma", "components", "f_min", "f_max", "seed", "crest", "focus_x",
                                           "focus_t", "file", "column", "ramp", "start", "end", "awas"};
  std::vector<std::string> allowed = type == "translation" ? std::vector<std::string>{"type", "velocity", "start", "end"}
                                     : type == "rotation"  ? std::vector<std::string>{"type", "center", "omega", "start", "end"}
                                     : type == "piston" || type == "flap" ? wavemaker
                                                           : std::vector<std::string>{"type", "amplitude", "frequency", "phase", "start", "end"};
  if (type == "flap") allowed.push_back("hinge");
  for (auto it = m.begin(); it != m.end(); ++it)
    if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end()) {
      const auto guess = scene::closest_key(it.key(), allowed);
      throw InputError(where + ": unknown key '" + it.key() + "' for a " + type + " motion" +
                       (guess ? " (did you mean '" + *guess + "'?)" : ""));
    }
  law.start = number_of(m, where, "start", 0.0);
  law.end = number_of(m, where, "end", 1e300);
  if (type == "translation") {
    law.type = MotionLaw<D>::Type::Translation;
    law.velocity = vec_of<D>(m, where, "velocity");
  } else if (type == "rotation") {
    law.type = MotionLaw<D>::Type::Rotation;
    law.center = vec_of<D>(m, where, "center");
    if (D == 2) {
      law.omega.z() = number_of(m, where, "omega", 0, true);  // rad/s, counter-clockwise
    } else {
      const Vec<D> w = vec_of<D>(m, where, "omega");  // rad/s about the axis w/|w|
      for (int a = 0; a < D; ++a) law.omega[a] = double(w[a]);
    }
  } else if (type == "oscillation") {
    law.type = MotionLaw<D>::Type::Oscillation;
    law.amplitude = vec_of<D>(m, where, "amplitude");
    law.frequency = number_of(m, where, "frequency", 0, true);
    if (!(law.frequency > 0)) throw InputError(where + ".frequency: expected a positive number [Hz]");
    law.phase = number_of(m, where, "phase", 0.0);
  } else if (type == "piston" || type == "flap") {
    law.type = type == "piston" ? MotionLaw<D>::Type::Piston : MotionLaw<D>::Type::Flap;
    parse_wavemaker<D>(m, where, sc, body, law);
  } else {
    throw InputError(where + ".type: expected \"translation\", \"rotation\", \"oscillation\", \"piston\" or \"flap\", got \"" +
                     type + "\"");
  }
  return law;
}

template <int D>
BoundaryMotion<D>::BoundaryMotion(std::vector<MotionLaw<D>> laws, ParticleStore& store) : laws_(std::move(laws)) {
  for (const auto& l : laws_) {
    active_ |= l.type != MotionLaw<D>::Type::None;
    absorbing_ |= l.awas.on;
  }
  paddle_.resize(laws_.size());
  awas_.resize(laws_.size());
  if (!active_) return;
  x0_ = &store.add<Vec<D>>("reference_position", {.exported = false});
  n0_ = &store.add<Vec<D>>("reference_normal", {.exported = false});
}

template <int D>
void BoundaryMotion<D>::capture_reference(const Field<Vec<D>>& x, const Field<Vec<D>>& normal) {
  if (!active_) return;
  x0_->data = x.data;
  n0_->data = normal.data;
}

namespace {
// the flap's rotation axis: z in 2D (angle -theta), y in 3D (angle +theta): the top moves towards +x
template <int D>
Eigen::Vector3d flap_axis() {
  return D == 2 ? Eigen::Vector3d(0, 0, -1) : Eigen::Vector3d(0, 1, 0);
}
}  // namespace

template <int D>
waves::PaddleState BoundaryMotion<D>::paddle_state(const MotionLaw<D>& law, double t, const AbsorptionState* c) const {
  const double tau = std::clamp(t, law.start, law.end) - law.start;
  waves::PaddleState s = law.paddle->at(tau);
  if (c) {  // the absorption's correction, held at U_c over the step (also after `end`), added at the still-water level
    if (!(t >= law.start && t <= law.end)) s.dq = s.ddq = 0;
    s.q += c->shift + (t - c->t_ref) * c->u;
    s.dq += c->u;
    if (law.type != MotionLaw<D>::Type::Flap) return s;
    // a flap: the corrected X(t) turns it by atan(X / a) (X'' the signal's, as the piston's acceleration)
    const double a = law.arm, q2 = a * a + s.q * s.q;
    return {std::atan2(s.q, a), a * s.dq / q2, a * s.ddq / q2 - 2 * a * s.q * s.dq * s.dq / (q2 * q2)};
  }
  if (law.type == MotionLaw<D>::Type::Flap && !law.paddle_angle) {
    // theta = atan(X / a): the flap's top at the still-water level moves by X (a = h - l, its wetted arm)
    const double a = law.arm, q2 = a * a + s.q * s.q;
    s = {std::atan2(s.q, a), a * s.dq / q2, a * s.ddq / q2 - 2 * a * s.q * s.dq * s.dq / (q2 * q2)};
  }
  if (!(t >= law.start && t <= law.end)) s.dq = s.ddq = 0;
  return s;
}

template <int D>
void BoundaryMotion<D>::evaluate(const MotionLaw<D>& law, const waves::PaddleState& paddle, double t, const Vec<D>& x0,
                                 Vec<D>& x, Vec<D>& v, Eigen::Matrix<Real, D, D>& R) const {
  using T = typename MotionLaw<D>::Type;
  R.setIdentity();
  const bool moving = t >= law.start && t <= law.end;
  const double tau = std::clamp(t, law.start, law.end) - law.start;  // time spent moving
  v.setZero();
  switch (law.type) {
    case T::None: x = x0; return;
    case T::Translation:
      x = x0 + Real(tau) * law.velocity;
      if (moving) v = law.velocity;
      return;
    case T::Rotation: {
      const double rate = law.omega.norm();
      Eigen::Matrix3d R3 = Eigen::Matrix3d::Identity();
      if (rate > 0) R3 = Eigen::AngleAxisd(rate * tau, law.omega / rate).toRotationMatrix();
      R = R3.topLeftCorner<D, D>().template cast<Real>();
      x = law.center + R * (x0 - law.center);
      if (moving) {
        Eigen::Vector3d r = Eigen::Vector3d::Zero();
        for (int a = 0; a < D; ++a) r[a] = double(x[a] - law.center[a]);
        const Eigen::Vector3d w = law.omega.cross(r);
        for (int a = 0; a < D; ++a) v[a] = Real(w[a]);
      }
      return;
    }
    case T::Oscillation: {
      const double w = 2 * std::numbers::pi * law.frequency;
      x = x0 + Real(std::sin(w * tau + law.phase) - std::sin(law.phase)) * law.amplitude;
      if (moving) v = Real(w * std::cos(w * tau + law.phase)) * law.amplitude;
      return;
    }
    case T::Piston:  // x = x0 + X e_x
      x = x0;
      x[0] += Real(paddle.q);
      v[0] = Real(paddle.dq);
      return;
    case T::Flap: {  // rotation by theta about the hinge
      const Eigen::Vector3d e = flap_axis<D>();
      const Eigen::Matrix3d R3 = Eigen::AngleAxisd(paddle.q, e).toRotationMatrix();
      R = R3.topLeftCorner<D, D>().template cast<Real>();
      x = law.center + R * (x0 - law.center);
      Eigen::Vector3d r = Eigen::Vector3d::Zero();
      for (int a = 0; a < D; ++a) r[a] = double(x[a] - law.center[a]);
      const Eigen::Vector3d w = (paddle.dq * e).cross(r);
      for (int a = 0; a < D; ++a) v[a] = Real(w[a]);
      return;
    }
  }
}

template <int D>
Vec<D> BoundaryMotion<D>::acceleration(const MotionLaw<D>& law, const waves::PaddleState& paddle, double t,
                                       const Vec<D>& x) const {
  using T = typename MotionLaw<D>::Type;
  if (!(t >= law.start && t <= law.end)) return Vec<D>::Zero();
  switch (law.type) {
    case T::None:
    case T::Translation: return Vec<D>::Zero();
    case T::Rotation: {  // centripetal: omega x (omega x r)
      Eigen::Vector3d r = Eigen::Vector3d::Zero();
      for (int a = 0; a < D; ++a) r[a] = double(x[a] - law.center[a]);
      const Eigen::Vector3d acc = law.omega.cross(law.omega.cross(r));
      Vec<D> out;
      for (int a = 0; a < D; ++a) out[a] = Real(acc[a]);
      return out;
    }
    case T::Oscillation: {  // d^2/dt^2 of A sin(w tau + phi)
      const double w = 2 * std::numbers::pi * law.frequency;
      return Real(-w * w * std::sin(w * (t - law.start) + law.phase)) * law.amplitude;
    }
    case T::Piston: {
      Vec<D> out = Vec<D>::Zero();
      out[0] = Real(paddle.ddq);
      return out;
    }
    case T::Flap: {  // angular acceleration x r + centripetal
      Eigen::Vector3d r = Eigen::Vector3d::Zero();
      for (int a = 0; a < D; ++a) r[a] = double(x[a] - law.center[a]);
      const Eigen::Vector3d e = flap_axis<D>(), w = paddle.dq * e;
      const Eigen::Vector3d acc = (paddle.ddq * e).cross(r) + w.cross(w.cross(r));
      Vec<D> out;
      for (int a = 0; a < D; ++a) out[a] = Real(acc[a]);
      return out;
    }
  }
  return Vec<D>::Zero();
}

template <int D>
void BoundaryMotion<D>::apply(double t, Field<Vec<D>>& x, Field<Vec<D>>& v, Field<Vec<D>>& normal,
                              const Field<std::int32_t>& body, Field<Vec<D>>* acc) const {
  if (!active_) return;
  // each wavemaker's signal once per call (a spectrum's hundreds of components are not summed per particle)
  for (std::size_t k = 0; k < laws_.size(); ++k) {
    if (!laws_[k].paddle) continue;
    paddle_[k] = paddle_state(laws_[k], t, laws_[k].awas.on ? &awas_[k] : nullptr);
  }
  const waves::PaddleState* paddle = paddle_.data();
  for_each_particle(x.size(), [&](std::size_t i) {
    const int b = body[i];
    if (b < 0 || std::size_t(b) >= laws_.size() || laws_[b].type == MotionLaw<D>::Type::None) return;
    Eigen::Matrix<Real, D, D> R;
    evaluate(laws_[b], paddle[b], t, (*x0_)[i], x[i], v[i], R);
    normal[i] = R * (*n0_)[i];
    if (acc) (*acc)[i] = acceleration(laws_[b], paddle[b], t, x[i]);
  });
}

namespace {
// the linear-theory target elevation of a law at time t, x from the paddle's face at rest (zero outside the law's
// [start, end]: a stopped paddle targets still water); ramped as the signal is
template <int D>
double target_elevation(const MotionLaw<D>& law, double t, double x) {
  const auto& A = law.awas;
  if (!(t >= law.start && t <= law.end)) return 0;
  const double tau = t - law.start;
  const double r = tau < A.ramp ? 0.5 * (1 - std::cos(std::numbers::pi * tau / A.ramp)) : 1.0;
  double eta = 0;
  for (std::size_t i = 0; i < A.target.size(); ++i) {
    const auto& c = A.target[i];
    eta += c.amplitude * std::cos(c.omega * tau + c.phase - A.k[i] * x);
  }
  return r * eta;
}

std::string hex_of(double v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(std::bit_cast<std::uint64_t>(v)));
  return buf;
}
double of_hex(const json& j) { return std::bit_cast<double>(std::uint64_t(std::stoull(j.get<std::string>(), nullptr, 16))); }
}  // namespace

template <int D>
void BoundaryMotion<D>::absorb(double t, const std::function<double(double, double)>& level) {
  for (std::size_t k = 0; k < laws_.size(); ++k) {
    const auto& law = laws_[k];
    if (!law.awas.on) continue;
    const auto& A = law.awas;
    auto& s = awas_[k];
    s.shift += (t - s.t_ref) * s.u;  // X_c(t): the same expression apply() evaluated at t (the same bits)
    s.t_ref = t;
    // the paddle's displacement at t at the still-water level (a flap's face moves by X there, to O(theta^3))
    const double X = law.paddle->at(std::clamp(t, law.start, law.end) - law.start).q + s.shift;
    const double lv = level(A.face + X + A.gauge, A.across);
    if (!s.have_level0) {  // the still-water reading removes the gauge's own offset (particle rows, kernel)
      s.level0 = lv;
      s.have_level0 = true;
    }
    s.eta_measured = lv - s.level0;
    s.eta_target = target_elevation(law, t, X + A.gauge);
    if (t < A.start) {
      s.u = 0;
      continue;
    }
    // Altomare et al. 2017 eq. 12 (Schaffer & Klopman 2000): U_c = G (eta_T - eta_M); drift: - X_c / T_d
    s.u = A.gain * (s.eta_target - s.eta_measured) - (A.drift_time > 0 ? s.shift / A.drift_time : 0.0);
  }
}

template <int D>
nlohmann::json BoundaryMotion<D>::save_state() const {
  json a = json::array();
  for (std::size_t k = 0; k < laws_.size(); ++k) {
    if (!laws_[k].awas.on) continue;
    const auto& s = awas_[k];
    a.push_back({{"law", k}, {"t_ref", hex_of(s.t_ref)}, {"shift", hex_of(s.shift)}, {"u", hex_of(s.u)},
                 {"level0", hex_of(s.level0)}, {"have_level0", s.have_level0}, {"eta_target", hex_of(s.eta_target)},
                 {"eta_measured", hex_of(s.eta_measured)}});
  }
  return a;
}

template <int D>
void BoundaryMotion<D>::restore_state(const nlohmann::json& j) {
  std::size_t n = 0;
  for (const auto& l : laws_) n += l.awas.on;
  if (!j.is_array() || j.size() != n)
    throw InputError("checkpoint: the active absorption state of " + std::to_string(n) + " paddles expected (motion.awas)");
  for (const auto& e : j) {
    const std::size_t k = e.at("law").get<std::size_t>();
    if (k >= laws_.size() || !laws_[k].awas.on) throw InputError("checkpoint: the absorbing paddles do not match the scene");
    auto& s = awas_[k];
    s.t_ref = of_hex(e.at("t_ref"));
    s.shift = of_hex(e.at("shift"));
    s.u = of_hex(e.at("u"));
    s.level0 = of_hex(e.at("level0"));
    s.have_level0 = e.at("have_level0").get<bool>();
    s.eta_target = of_hex(e.at("eta_target"));
    s.eta_measured = of_hex(e.at("eta_measured"));
  }
}

template class BoundaryMotion<2>;
template class BoundaryMotion<3>;
template MotionLaw<2> parse_motion<2>(const json&, const std::string&, const scene::Scene*, std::size_t);
template MotionLaw<3> parse_motion<3>(const json&, const std::string&, const scene::Scene*, std::size_t);

}  // namespace varsph
