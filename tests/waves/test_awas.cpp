// Active absorption at a piston or a flap (AWAS, `motion.awas`; docs/waves.md "Active absorption"): the paddle's velocity is
// corrected by G (eta_T - eta_M) from the elevation measured in front of it (Altomare et al. 2017, eq. 12, after
// Schaffer & Klopman 2000). A wave packet reflected by a wall at the far end is absorbed at the paddle, measured by
// the two-gauge method of Goda & Suzuki (1976) against the same run without it; the same bits on 1 and 2 threads;
// a restart continues bitwise (the correction's state is in the checkpoint); bad input is refused naming the key.
#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>

#include "core/errors.hpp"
#include "scene/scene.hpp"
#include "sim/simulation.hpp"
#include "restart_support.hpp"
#include "test_support.hpp"
#include "waves/wave_theory.hpp"

using namespace varsph;
using nlohmann::json;

namespace {

constexpr double kDepth = 0.1, kG = 9.81;

// A small 2D flume: water `length` x 0.1 m at dx = 1 cm, a wall at the far end and no damping zone, the piston
// (body 3) a block of three layers left of the water. The engineering set-up (docs/validation.md).
json flume(const json& motion, double length = 1.0) {
  json j = json::parse(R"({
    "name": "flume", "setup": "paper", "dimension": 2,
    "domain": {"min": [-0.3, -0.1], "max": [1.2, 0.4]}, "particles": {"spacing": 0.01},
    "kernel": {"type": "wendland_c2", "h_over_dx": 1.414}, "gravity": [0, -9.81],
    "physics": {"riemann": {}}, "boundary": {"model": "dummy_adami"},
    "integrator": {"type": "symplectic_euler", "cfl": 0.2}, "time": {"end": 1},
    "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0], "max": [1.0, 0.1], "initial_pressure": "hydrostatic"},
               {"kind": "boundary", "shape": "box", "min": [-0.25, -0.03], "max": [1.03, 0], "layers": 3},
               {"kind": "boundary", "shape": "box", "min": [1.0, 0], "max": [1.03, 0.2], "layers": 3},
               {"kind": "boundary", "shape": "box", "min": [-0.03, 0], "max": [0, 0.16], "layers": 3}]})");
  j["domain"]["max"][0] = length + 0.2;
  j["bodies"][0]["max"][0] = length;
  j["bodies"][1]["max"][0] = length + 0.03;
  j["bodies"][2]["min"][0] = length;
  j["bodies"][2]["max"][0] = length + 0.03;
  j["bodies"][3]["motion"] = motion;
  return j;
}

json piston(double H, double T, double ramp) {
  return {{"type", "piston"}, {"waves", "regular"}, {"height", H}, {"period", T}, {"ramp", ramp}};
}

// The same paddle block as a flap turning about `hinge` (default: the middle of its foot, on the bed).
json flap(double H, double T, double ramp, double hinge_y = 0.0) {
  json m = piston(H, T, ramp);
  m["type"] = "flap";
  m["hinge"] = {-0.015, hinge_y};
  return m;
}

// The complex amplitude Z of the component at omega of a record (least squares of a cos + b sin about the mean):
// eta ~ Re(Z e^{i omega t}).
std::complex<double> component(const std::vector<double>& t, const std::vector<double>& e, double omega) {
  double mean = 0;
  for (double v : e) mean += v;
  mean /= double(e.size());
  double cc = 0, cs = 0, ss = 0, ec = 0, es = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double c = std::cos(omega * t[i]), s = std::sin(omega * t[i]), v = e[i] - mean;
    cc += c * c;
    cs += c * s;
    ss += s * s;
    ec += v * c;
    es += v * s;
  }
  const double det = cc * ss - cs * cs, a = (ec * ss - es * cs) / det, b = (es * cc - ec * cs) / det;
  return {a, -b};
}

struct Split {
  double towards_wall = 0, towards_paddle = 0;  // |a_I| (+x), |a_R| (-x) [m]
};

// Goda & Suzuki (1976) at one frequency: Z1 = a_I + a_R, Z2 = a_I e^{-ik dl} + a_R e^{ik dl}.
Split goda_suzuki(std::complex<double> Z1, std::complex<double> Z2, double k, double dl) {
  const std::complex<double> i(0, 1), s = 2.0 * i * std::sin(k * dl);
  return {std::abs((Z1 * std::exp(i * k * dl) - Z2) / s), std::abs((Z2 - Z1 * std::exp(-i * k * dl)) / s)};
}

// A packet of regular waves (H = 2 cm, T = 1 s, kh = 0.67, L = 0.94 m; ramp 1 T, the paddle stops at 2.5 s) runs
// to the wall 1 m away and back. Without absorption the paddle re-reflects it; with AWAS it absorbs it. Over the
// window 3.2-5.5 s, when the waves that travel towards the wall are only those the paddle sent back, Goda & Suzuki
// on two gauges (0.3 and 0.5 m, k dl = 0.43 pi) separates them from those coming from the wall: the paddle's
// reflection is their ratio.
struct Packet {
  Split off, on;
  double r_off() const { return off.towards_wall / off.towards_paddle; }
  double r_on() const { return on.towards_wall / on.towards_paddle; }
};

Packet packet_reflection(const json& paddle, const json& awas) {
  const double T = paddle["period"].get<double>(), omega = 2 * std::numbers::pi / T;
  const double k = waves::wave_number(omega, kDepth, kG);
  const double x1 = 0.3, x2 = 0.5, t0 = 3.2, t1 = 5.5;
  auto run = [&](bool on) {
    omp_set_num_threads(1);  // one core: two runs of 27 000 steps (about 10 s each on an idle core)
    json m = paddle;
    m["end"] = 2.5;
    if (on) m["awas"] = awas;
    json j = flume(m);
    j["time"]["end"] = t1;
    Simulation<2> sim(scene::parse_scene_json(j, "awas.json"));
    std::vector<double> t, e1, e2;
    const double still1 = sim.free_surface_level(x1, 0), still2 = sim.free_surface_level(x2, 0);
    double next = t0;
    while (sim.time() < t1) {
      sim.advance();
      if (sim.time() >= next) {
        t.push_back(sim.time());
        e1.push_back(sim.free_surface_level(x1, 0) - still1);
        e2.push_back(sim.free_surface_level(x2, 0) - still2);
        next += 0.01;
      }
    }
    return goda_suzuki(component(t, e1, omega), component(t, e2, omega), k, x2 - x1);
  };
  Packet p{run(false), run(true)};
  std::printf("%s: paddle reflection without AWAS %.3f (a_I %.5f m, a_R %.5f m), with AWAS %.3f (a_I %.5f m, a_R %.5f m)\n",
              paddle["type"].get<std::string>().c_str(), p.r_off(), p.off.towards_wall, p.off.towards_paddle, p.r_on(),
              p.on.towards_wall, p.on.towards_paddle);
  return p;
}

}  // namespace

// Measured (2026-11-27): 1.00 without, 0.39 with AWAS (shallow-water gain sqrt(g/h)).
TEST(Awas, AbsorbsAtThePaddleTheWaveReflectedByTheFarWall) {
  const Packet p = packet_reflection(piston(0.02, 1.0, 1.0), json::object());
  EXPECT_GT(p.r_off(), 0.8);  // a still piston is a wall
  EXPECT_LT(p.r_on(), 0.5);   // measured 0.39
  EXPECT_LT(p.on.towards_wall, 0.3 * p.off.towards_wall);  // the wave sent back, absolute: measured 0.23
  EXPECT_GT(p.on.towards_paddle, 0.0015);  // the wall's reflection arrived (not vacuous): measured 0.0039 m
}

// The same packet made by a flap hinged on the bed (stroke 57 mm at the still-water level, up to 16 degrees), its
// correction turned into an angle with the flap's shallow gain 2 sqrt(g/h) (docs/waves.md "a flap"). Bounds: the
// piston's (what is left there is the gauge's phase lead and the stop's broad-band tail, which a flap shares; the
// flap's shallow gain is 11 % above omega / (H/S) at this kh, the piston's 7 %). Measured (2026-11-28): 1.05 held
// still, 0.43 with AWAS; the wave sent back 1.6 mm against 6.4 mm (x 0.24).
TEST(Awas, AFlapAbsorbsAtThePaddleTheWaveReflectedByTheFarWall) {
  const Packet p = packet_reflection(flap(0.02, 1.0, 1.0), json::object());
  EXPECT_GT(p.r_off(), 0.8);  // a still flap is a wall
  EXPECT_LT(p.r_on(), 0.5);   // measured 0.43
  EXPECT_LT(p.on.towards_wall, 0.3 * p.off.towards_wall);  // measured 0.24
  EXPECT_GT(p.on.towards_paddle, 0.0015);  // the wall's reflection arrived (not vacuous): measured 0.0037 m
}

// The flap's gain: the shallow-water form sqrt(g/h) (h - l) / (h/2 - l) for a hinge l <= 0 above the bed (2 sqrt(g/h)
// on the bed, the piston's sqrt(g/h) as l -> -inf) is the kh -> 0 limit of the linear form omega / (H/S)(kh) with
// the flap's transfer function; at the wave's own kh the linear form is omega over the flap's H/S.
TEST(Awas, AFlapsGainIsTheDepthAveragedShallowWaterLimitOfItsTransfer) {
  const double c = std::sqrt(kG / kDepth);
  auto gain = [](const json& m) {
    Simulation<2> sim(scene::parse_scene_json(flume(m), "awas.json"));
    return sim.motion().laws()[3].awas.gain;
  };
  for (double l : {0.0, -0.015, -0.05}) {
    json m = flap(0.01, 1.0, 1.0, l);
    m["awas"] = json::object();
    const double shallow = gain(m);
    EXPECT_NEAR(shallow, c * (kDepth - l) / (0.5 * kDepth - l), 1e-12 * c) << "hinge " << l;
    m["awas"]["gain"] = "linear";
    const double w = 2 * std::numbers::pi, k = waves::wave_number(w, kDepth, kG);
    EXPECT_NEAR(gain(m), w / waves::flap_transfer(k, kDepth, l), 1e-12 * c) << "hinge " << l;
    // the shallow form is the long-wave limit of the linear one: kh = 0.021 (T = 30 s, H 1 mm)
    json lw = flap(0.001, 30.0, 30.0, l);
    lw["awas"] = {{"gain", "linear"}};
    const double kl = waves::wave_number(2 * std::numbers::pi / 30.0, kDepth, kG);
    ASSERT_LT(kl * kDepth, 0.025);
    EXPECT_NEAR(gain(lw) / shallow, 1.0, 1e-3) << "hinge " << l;  // O((kh)^2)
  }
}

TEST(Awas, TwoThreadsGiveTheBitsOfOne) {
  for (const bool is_flap : {false, true}) {
    auto run = [is_flap](int threads, bool awas) {
      omp_set_num_threads(threads);
      json m = is_flap ? flap(0.01, 1.0, 0) : piston(0.01, 1.0, 0);
      if (awas) m["awas"] = {{"start", 0.0}};  // corrects from the first step
      Simulation<2> sim(scene::parse_scene_json(flume(m), "awas.json"));
      for (int n = 0; n < 40; ++n) sim.advance();
      omp_set_num_threads(1);
      std::map<std::int64_t, std::array<double, 4>> by_id;
      const auto& f = sim.fields();
      for (std::size_t i = 0; i < sim.size(); ++i)
        by_id[f.id[i]] = {double(f.x[i][0]), double(f.x[i][1]), double(f.v[i][0]), double(f.v[i][1])};
      const auto& s = sim.motion().absorption()[3];
      by_id[-1] = {s.shift, s.u, s.eta_measured, s.eta_target};
      return by_id;
    };
    const auto one = run(1, true);
    EXPECT_TRUE(one == run(2, true)) << (is_flap ? "flap" : "piston");
    EXPECT_NE(one.at(-1)[1], 0.0);          // the correction acts
    EXPECT_FALSE(one == run(1, false));     // and changes the run
  }
}

TEST(Awas, ARestartContinuesBitwise) {
  namespace fs = std::filesystem;
  for (const bool is_flap : {false, true}) {
    const fs::path dir = test::scratch_dir(is_flap ? "awas_restart_flap" : "awas_restart");
    json m = is_flap ? flap(0.01, 1.0, 0) : piston(0.01, 1.0, 0);
    m["awas"] = {{"start", 0.0}, {"drift_time", 5.0}};
    json j = flume(m);
    j["time"]["end"] = 0.04;
    j["output"] = {{"every", 0.02}, {"probes_every", 0.002}};
    j["checkpoint"] = {{"every", 0.02}};
    j["probes"] = {{{"type", "water_height"}, {"name", "g1"}, {"from", {0.3, 0.0}}},
                   {{"type", "force"}, {"name", "paddle"}, {"body", 3}}};
    std::ofstream(dir / "scene.json") << j.dump(1);
    const auto t = test::run_full_and_restarted(dir / "scene.json", dir, "0.02", "probes.csv");
    ASSERT_TRUE(t.error.empty()) << t.error;
    const std::string& full = t.full;
    EXPECT_EQ(full, t.continued);
    EXPECT_GT(std::count(full.begin(), full.end(), '\n'), 15);
    // not vacuous: without the correction's state the paddle restarts elsewhere (the force probe differs)
    j["bodies"][3]["motion"].erase("awas");
    std::ofstream(dir / "plain.json") << j.dump(1);
    const auto r = test::run_command(test::varsph_exe().string() + " run " + (dir / "plain.json").string() + " -o " +
                                     (dir / "plain").string() + " --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(full, test::read_text(dir / "plain" / "probes.csv"));
  }
}

TEST(Awas, BadInputIsRefusedNamingTheKey) {
  const std::string dir = test::scratch_dir("awas_bad").string();
  std::ofstream(dir + "/paddle.csv") << "time,displacement\n0,0\n1,0.001\n";
  struct Case {
    json motion;
    std::string key, limit;
  };
  json high = flap(0.01, 1.0, 1.0, 0.02);  // a flap hinged 2 cm above the bed
  high["awas"] = json::object();
  json file = {{"type", "piston"}, {"waves", "file"}, {"file", "paddle.csv"}, {"awas", json::object()}};
  json near = piston(0.01, 1.0, 1.0);
  near["awas"] = {{"gauge", 0.01}};
  json gain = piston(0.01, 1.0, 1.0);
  gain["awas"] = {{"gain", "deep"}};
  json drift = piston(0.01, 1.0, 1.0);
  drift["awas"] = {{"drift_time", -1.0}};
  json typo = piston(0.01, 1.0, 1.0);
  typo["awas"] = {{"gague", 0.05}};
  json kind = piston(0.01, 1.0, 1.0);
  kind["awas"] = 3;
  const Case cases[] = {{high, "motion.hinge", "at the bed or below it"},
                        {file, "motion.awas", "wave-theory signal"},
                        {near, "motion.awas.gauge", "at least 2h"},
                        {gain, "motion.awas.gain", "\"shallow\""},
                        {drift, "motion.awas.drift_time", ">= 0"},
                        {typo, "motion.awas", "did you mean 'gauge'"},
                        {kind, "motion.awas", "expected an object"}};
  for (const auto& c : cases) {
    std::string what;
    try {
      Simulation<2> sim(scene::parse_scene_json(flume(c.motion), dir + "/scene.json"));
      what = "accepted";
    } catch (const InputError& e) {
      what = e.what();
    }
    EXPECT_NE(what.find(c.key), std::string::npos) << c.motion.dump() << ": " << what;
    EXPECT_NE(what.find(c.limit), std::string::npos) << c.motion.dump() << ": " << what;
  }
  // and the command exits 2 naming the file and the key
  json j = flume(near);
  std::ofstream(dir + "/near.json") << j.dump(1);
  const auto r = test::run_command(test::varsph_exe().string() + " run " + dir + "/near.json -o " + dir + "/out --quiet");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("near.json"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bodies.3.motion.awas.gauge"), std::string::npos) << r.output;
}
