#include "scene/parse_rigid.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Dense>

namespace varsph::scene {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
std::string at(const std::string& base, const std::string& key) { return base + "." + key; }

double norm_of(const std::vector<double>& v) {
  double q = 0;
  for (double x : v) q += x * x;
  return std::sqrt(q);
}

}  // namespace

void parse_rigid_body(JsonReader& r, const std::string& base, int dim, BodySpec& b) {
  RigidSpec& g = b.rigid;
  // 0: the whole solid is sampled (no fluid can be trapped inside); N: N layers inside its surface
  b.layers = int(r.integer(at(base, "layers"), 0, 0, 1000));
  if (b.shape == "cylinder" && dim == 3) {
    g.cylinder_axis = r.vector(at(base, "axis"), 3, std::nullopt, "cylinder axis direction");
    if (!(norm_of(g.cylinder_axis) > 0)) r.fail_got(at(base, "axis"), "a direction of non-zero length", json(g.cylinder_axis));
    g.cylinder_length = r.positive(at(base, "length"), std::nullopt, "cylinder length along its axis [m]");
  }
  const bool has_density = r.has(at(base, "density")), has_mass = r.has(at(base, "mass"));
  if (has_density == has_mass)
    r.fail(at(base, "density"), "exactly one of \"density\" (a uniform solid, kg/m^3) or \"mass\" (kg; 2D: kg per metre)");
  if (has_density) {
    g.density = r.positive(at(base, "density"), std::nullopt, "density of the solid [kg/m^3]");
    for (const char* k : {"center_of_mass", "inertia"})
      if (r.has(at(base, k))) r.fail(at(base, k), std::string("no \"") + k + "\" with \"density\" (they follow from the shape)");
  } else {
    g.mass = r.positive(at(base, "mass"), std::nullopt, "mass of the body [kg] (2D: kg per metre)");
    if (r.has(at(base, "center_of_mass")))
      g.center_of_mass = r.vector(at(base, "center_of_mass"), std::size_t(dim), std::nullopt, "centre of mass [m]");
    if (r.has(at(base, "inertia"))) {
      if (dim == 2) {
        g.inertia = {r.positive(at(base, "inertia"), std::nullopt, "moment of inertia about z through the centre of mass [kg m^2 / m]")};
      } else {
        g.inertia = r.vector(at(base, "inertia"), 6, std::nullopt, "inertia tensor about the centre of mass {Ixx, Iyy, Izz, Ixy, Ixz, Iyz} [kg m^2]");
        Eigen::Matrix3d I;
        I << g.inertia[0], g.inertia[3], g.inertia[4], g.inertia[3], g.inertia[1], g.inertia[5], g.inertia[4],
            g.inertia[5], g.inertia[2];
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(I);
        const auto ev = es.eigenvalues();
        if (!(ev.minCoeff() > 0))
          r.fail_got(at(base, "inertia"), "a symmetric positive definite tensor (its smallest eigenvalue is " +
                                              std::to_string(ev.minCoeff()) + ")", json(g.inertia));
        // a physical body: each principal moment at most the sum of the other two (triangle inequality)
        if (ev[2] > (ev[0] + ev[1]) * (1 + 1e-9))
          r.fail_got(at(base, "inertia"), "principal moments that a body can have (each <= the sum of the other two)", json(g.inertia));
      }
    }
  }
  const std::size_t nrot = dim == 2 ? 1 : 3;
  g.angular_velocity = r.vector(at(base, "angular_velocity"), nrot, std::vector<double>(nrot, 0.0), "initial angular velocity [rad/s]");
  g.lock_translation = r.bools(at(base, "lock_translation"), std::size_t(dim), std::vector<bool>(std::size_t(dim), false));
  g.lock_rotation = r.bools(at(base, "lock_rotation"), nrot, std::vector<bool>(nrot, false));
  g.constraint = r.choice(at(base, "constraint.type"), "free", {"free", "hinge", "fixed_point"});
  if (g.constraint != "free") {
    g.pivot = r.vector(at(base, "constraint.point"), std::size_t(dim), std::nullopt, "a point of the hinge axis / the fixed point [m]");
    for (bool l : g.lock_translation)
      if (l) r.fail(at(base, "lock_translation"), "no translation locks with a " + g.constraint + " (it fixes the point already)");
  }
  if (g.constraint == "hinge" && dim == 3) {
    g.axis = r.vector(at(base, "constraint.axis"), 3, std::nullopt, "hinge axis direction");
    if (!(norm_of(g.axis) > 0)) r.fail_got(at(base, "constraint.axis"), "a direction of non-zero length", json(g.axis));
  }
  if (g.constraint == "hinge" && dim == 2) g.constraint = "fixed_point";  // in 2D a hinge about z is a fixed point
}

void parse_moorings_and_contact(JsonReader& r, Scene& s) {
  const int dim = s.dimension;
  const std::size_t n = r.array_size("moorings");
  for (std::size_t k = 0; k < n; ++k) {
    const std::string base = "moorings." + std::to_string(k);
    MooringSpec m;
    auto rigid_index = [&](const std::string& key) {
      const long i = r.integer(key, std::nullopt, 0, long(s.bodies.size()) - 1);
      if (s.bodies[std::size_t(i)].kind != "rigid")
        r.fail(key, "the index of a body with kind \"rigid\" (body " + std::to_string(i) + " is " + s.bodies[std::size_t(i)].kind + ")");
      return int(i);
    };
    m.body = rigid_index(at(base, "body"));
    m.point = r.vector(at(base, "point"), std::size_t(dim), std::nullopt, "attachment point on the body at t = 0 [m]");
    if (r.has(at(base, "anchor_body"))) {
      m.anchor_body = rigid_index(at(base, "anchor_body"));
      if (m.anchor_body == m.body) r.fail(at(base, "anchor_body"), "another body than `body`");
    }
    m.anchor = r.vector(at(base, "anchor"), std::size_t(dim), std::nullopt,
                        m.anchor_body < 0 ? "fixed anchor point [m]" : "attachment point on anchor_body at t = 0 [m]");
    m.stiffness = r.positive(at(base, "stiffness"), std::nullopt, "spring stiffness [N/m] (2D: per metre of depth)");
    m.damping = r.number(at(base, "damping"), 0.0, 0, kInf, "damping coefficient [N s/m]");
    m.rest_length = r.number(at(base, "rest_length"), -1.0, -1, kInf, "unstretched length [m] (-1: the initial distance)");
    m.slack = r.boolean(at(base, "slack"), true);
    double d2 = 0;
    for (int a = 0; a < dim; ++a) d2 += (m.point[std::size_t(a)] - m.anchor[std::size_t(a)]) * (m.point[std::size_t(a)] - m.anchor[std::size_t(a)]);
    if (!(d2 > 0) && !(m.rest_length > 0))
      r.fail(at(base, "anchor"), "an anchor apart from the attachment point (a line of zero length has no direction)");
    s.moorings.push_back(m);
  }
  ContactSpec& c = s.contact;
  if (!s.has_rigid_bodies()) {  // nothing of this is read (or resolved) for scenes without rigid bodies
    if (r.has("contact")) r.fail("contact", "a body with kind \"rigid\" (contact acts between rigid bodies and walls)");
    c.enabled = false;
    return;
  }
  c.enabled = r.boolean("contact.enabled", true);
  c.distance = r.number("contact.distance", 1.0, 0.1, 2.0, "contact distance between boundary particles [dx]");
  const json* st = r.raw("contact.stiffness");
  if (st && st->is_string() && st->get<std::string>() == "auto") {
    r.text("contact.stiffness", "auto");
  } else if (st && !st->is_null()) {
    c.stiffness = r.positive("contact.stiffness", std::nullopt, "stiffness of a particle pair [N/m] or \"auto\"");
  } else {
    r.text("contact.stiffness", "auto");
  }
  c.restitution = r.number("contact.restitution", 0.5, 0.01, 1.0, "normal restitution of a particle pair");
}

}  // namespace varsph::scene
