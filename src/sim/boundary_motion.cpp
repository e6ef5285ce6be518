#include "sim/boundary_motion.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/errors.hpp"
#include "scene/key_suggest.hpp"
#include "physics/pair_loop.hpp"

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

}  // namespace

template <int D>
MotionLaw<D> parse_motion(const json& m, const std::string& where) {
  MotionLaw<D> law;
  if (m.is_null()) return law;
  if (!m.is_object() || !m.contains("type") || !m["type"].is_string())
    throw InputError(where + ": expected an object with \"type\": \"translation\" | \"rotation\" | \"oscillation\"");
  const std::string type = m["type"].get<std::string>();
  const std::vector<std::string> allowed = type == "translation" ? std::vector<std::string>{"type", "velocity", "start", "end"}
                                           : type == "rotation"  ? std::vector<std::string>{"type", "center", "omega", "start", "end"}
                                                                 : std::vector<std::string>{"type", "amplitude", "frequency", "phase", "start", "end"};
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
  } else {
    throw InputError(where + ".type: expected \"translation\", \"rotation\" or \"oscillation\", got \"" + type + "\"");
  }
  return law;
}

template <int D>
BoundaryMotion<D>::BoundaryMotion(std::vector<MotionLaw<D>> laws, ParticleStore& store) : laws_(std::move(laws)) {
  for (const auto& l : laws_) active_ |= l.type != MotionLaw<D>::Type::None;
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

template <int D>
void BoundaryMotion<D>::evaluate(const MotionLaw<D>& law, double t, const Vec<D>& x0, Vec<D>& x, Vec<D>& v,
                                 Eigen::Matrix<Real, D, D>& R) const {
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
  }
}

template <int D>
Vec<D> BoundaryMotion<D>::acceleration(const MotionLaw<D>& law, double t, const Vec<D>& x) const {
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
  }
  return Vec<D>::Zero();
}

template <int D>
void BoundaryMotion<D>::apply(double t, Field<Vec<D>>& x, Field<Vec<D>>& v, Field<Vec<D>>& normal,
                              const Field<std::int32_t>& body, Field<Vec<D>>* acc) const {
  if (!active_) return;
  for_each_particle(x.size(), [&](std::size_t i) {
    const int b = body[i];
    if (b < 0 || std::size_t(b) >= laws_.size() || laws_[b].type == MotionLaw<D>::Type::None) return;
    Eigen::Matrix<Real, D, D> R;
    evaluate(laws_[b], t, (*x0_)[i], x[i], v[i], R);
    normal[i] = R * (*n0_)[i];
    if (acc) (*acc)[i] = acceleration(laws_[b], t, x[i]);
  });
}

template class BoundaryMotion<2>;
template class BoundaryMotion<3>;
template MotionLaw<2> parse_motion<2>(const json&, const std::string&);
template MotionLaw<3> parse_motion<3>(const json&, const std::string&);

}  // namespace varsph
