// `varsph run` on the device backend through the host launch (`--device cuda_emulation`) against the same
// run on the CPU: frames and diagnostics (a device run writes a step's frame and checkpoint from its
// last-good copy while the next step runs), restarts from a device checkpoint on the CPU and back, the
// blow-up path, and `--device cuda` on a machine without a GPU. docs/gpu.md "Tests".
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "exec/device_backend.hpp"
#include "io/checkpoint.hpp"
#include "test_support.hpp"

using namespace varsph;

namespace {

std::string exe() { return test::varsph_exe().string(); }
std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }
const auto kPaper = test::source_dir() / "pipelines" / "dam_break_2d_paper.json";

// the paper's dam break for 0.02 s (200 steps): frames every 0.005 s, checkpoints every 0.01 s
const std::string kShort =
    " --quiet --set time.end=0.02 --set output.every=0.005 --set checkpoint.every=0.01 --set output.probes_every=0.0025";

std::vector<std::vector<std::string>> read_csv(const std::filesystem::path& p) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(p);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

// every numeric column but wall_seconds equal within `rel` (relative, absolute below 1e-300)
void expect_same_table(const std::filesystem::path& a, const std::filesystem::path& b, double rel) {
  const auto ta = read_csv(a), tb = read_csv(b);
  ASSERT_EQ(ta.size(), tb.size()) << a << " vs " << b;
  ASSERT_FALSE(ta.empty());
  const auto& head = ta[0];
  EXPECT_EQ(head, tb[0]);
  for (std::size_t r = 1; r < ta.size(); ++r) {
    ASSERT_EQ(ta[r].size(), tb[r].size());
    for (std::size_t c = 0; c < ta[r].size(); ++c) {
      if (head[c] == "wall_seconds" || ta[r][c].empty()) continue;
      const double x = std::stod(ta[r][c]), y = std::stod(tb[r][c]);
      EXPECT_LE(std::abs(x - y), rel * std::max(1.0, std::abs(x))) << head[c] << " row " << r << ": " << x << " vs " << y;
    }
  }
}

// positions of the fluid and boundary particles by id from a checkpoint
std::map<std::int64_t, std::vector<double>> positions(const std::filesystem::path& ckpt) {
  const io::Checkpoint c = io::read_checkpoint(ckpt);
  const io::CheckpointArray* x = c.find("position");
  const io::CheckpointArray* id = c.find("id");
  EXPECT_TRUE(x && id);
  std::map<std::int64_t, std::vector<double>> out;
  const std::size_t n = std::size_t(c.header.particles);
  const int d = x->components;
  for (std::size_t i = 0; i < n; ++i) {
    std::int64_t k;
    std::memcpy(&k, id->bytes.data() + i * sizeof(k), sizeof(k));
    std::vector<double> p(static_cast<std::size_t>(d));
    for (int a = 0; a < d; ++a) {
      if (x->type == ScalarType::Float64) std::memcpy(&p[std::size_t(a)], x->bytes.data() + (i * d + a) * 8, 8);
      else {
        float f;
        std::memcpy(&f, x->bytes.data() + (i * d + a) * 4, 4);
        p[std::size_t(a)] = f;
      }
    }
    out[k] = p;
  }
  return out;
}

double max_position_difference(const std::filesystem::path& a, const std::filesystem::path& b) {
  const auto pa = positions(a), pb = positions(b);
  EXPECT_EQ(pa.size(), pb.size());
  double m = 0;
  for (const auto& [id, p] : pa) {
    const auto it = pb.find(id);
    if (it == pb.end()) return INFINITY;
    for (std::size_t c = 0; c < p.size(); ++c) m = std::max(m, std::abs(p[c] - it->second[c]));
  }
  return m;
}

const double kDx = 0.005;  // the paper case's spacing [m]
const double kTolX = std::is_same_v<Real, double> ? 1e-9 * kDx : 1e-3 * kDx;
const double kTolRel = std::is_same_v<Real, double> ? 1e-9 : 1e-3;

}  // namespace

TEST(DeviceRuns, FramesDiagnosticsProbesAndCheckpointsMatchTheCpu) {
  const auto dir = test::scratch_dir("device_runs_outputs");
  const std::string probes =
      " --set 'probes=[{\"type\":\"pressure\",\"name\":\"p1\",\"point\":[0.005,0.02]},{\"type\":\"front\"}]'";
  auto r = test::run_command(exe() + " run " + q(kPaper) + " -o " + q(dir / "cpu") + kShort + probes);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::run_command(exe() + " run " + q(kPaper) + " -o " + q(dir / "dev") + kShort + probes + " --device cuda_emulation");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // frames written from the deferred downloads: the same steps, times and diagnostics
  expect_same_table(dir / "cpu" / "diagnostics.csv", dir / "dev" / "diagnostics.csv", kTolRel);
  expect_same_table(dir / "cpu" / "probes.csv", dir / "dev" / "probes.csv", kTolRel);
  for (int k = 0; k <= 4; ++k) {
    char name[64];
    std::snprintf(name, sizeof name, "dam_break_2d_paper_%06d.vtu", k);
    EXPECT_TRUE(std::filesystem::exists(dir / "dev" / "frames" / name)) << name;
  }
  EXPECT_EQ(test::read_text(dir / "cpu" / "dam_break_2d_paper.pvd"), test::read_text(dir / "dev" / "dam_break_2d_paper.pvd"));
  for (const char* ck : {"step_000000100.h5", "step_000000200.h5"}) {
    const auto a = dir / "cpu" / "checkpoints" / ck, b = dir / "dev" / "checkpoints" / ck;
    ASSERT_TRUE(std::filesystem::exists(b)) << b;
    EXPECT_LE(max_position_difference(a, b), kTolX) << ck;
  }
  const auto run_json = test::read_text(dir / "dev" / "run.json");
  EXPECT_NE(run_json.find("\"device\": \"cuda_emulation\""), std::string::npos);
}

TEST(DeviceRuns, ASceneWithoutMethodKeysRunsTheEngineeringSetUpAsOnTheCpu) {
  // issue 35: the default set-up (Wendland C2, Riemann dissipation, dummy walls, symplectic Euler at CFL 0.2)
  // runs on the device; a 2D dam break naming no method keys, 0.03 s on the CPU and through the host launch
  const auto dir = test::scratch_dir("device_runs_setup");
  const auto scene = dir / "plain.json";
  std::ofstream(scene) << R"({"name": "plain", "dimension": 2, "domain": {"min": [-0.1, -0.1], "max": [0.5, 0.4]},
    "particles": {"spacing": 0.01}, "gravity": [0, -9.81],
    "bodies": [{"kind": "fluid", "shape": "box", "min": [0, 0], "max": [0.1, 0.2]},
               {"kind": "boundary", "shape": "tank", "min": [0, 0], "max": [0.4, 0.3]}],
    "time": {"end": 0.03}, "output": {"every": 0.01}})";
  auto r = test::run_command(exe() + " run " + q(scene) + " -o " + q(dir / "cpu") + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::run_command(exe() + " run " + q(scene) + " -o " + q(dir / "dev") + " --quiet --device cuda_emulation");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_same_table(dir / "cpu" / "diagnostics.csv", dir / "dev" / "diagnostics.csv", kTolRel);
  std::filesystem::path last;
  for (const auto& e : std::filesystem::directory_iterator(dir / "cpu" / "checkpoints"))
    if (e.path().extension() == ".h5" && e.path().filename() > last.filename()) last = e.path();
  ASSERT_FALSE(last.empty());
  EXPECT_LE(max_position_difference(last, dir / "dev" / "checkpoints" / last.filename()), 2 * kTolX);  // kTolX is for dx = 0.005 m
  const auto run_json = test::read_text(dir / "dev" / "run.json");
  for (const char* want : {"\"setup\": \"engineering\"", "\"wendland_c2\"", "\"dummy_adami\"", "\"symplectic_euler\""})
    EXPECT_NE(run_json.find(want), std::string::npos) << want;
}

TEST(DeviceRuns, RestartMovesBetweenCpuAndDevice) {
  const auto dir = test::scratch_dir("device_runs_restart");
  for (const char* integrator : {"verlet", "variational"}) {
    const std::string set = std::string(" --set integrator.type=") + integrator;
    // the device's fixed point starts from the constant guess; the CPU's default extrapolates (issue 19)
    const std::string exe = "VARSPH_VARIATIONAL_PREDICTOR=constant " + ::exe();
    auto r = test::run_command(exe + " run " + q(kPaper) + " -o " + q(dir / (std::string("straight_") + integrator)) + kShort + set);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto straight = dir / (std::string("straight_") + integrator) / "checkpoints" / "step_000000200.h5";
    // device to t = 0.01 s, then the CPU; and the CPU to 0.01 s, then the device
    for (const auto& [first, second] : {std::pair{"cuda_emulation", "cpu"}, std::pair{"cpu", "cuda_emulation"}}) {
      const auto run = dir / (std::string(integrator) + "_" + first + "_then_" + second);
      r = test::run_command(exe + " run " + q(kPaper) + " -o " + q(run) + kShort + set +
                            " --set time.end=0.01 --device " + first);
      ASSERT_EQ(r.exit_code, 0) << r.output;
      r = test::run_command(exe + " run " + q(kPaper) + " --restart " + q(run / "checkpoints" / "step_000000100.h5") +
                            kShort + set + " --device " + second);
      ASSERT_EQ(r.exit_code, 0) << r.output;
      const auto end = run / "checkpoints" / "step_000000200.h5";
      ASSERT_TRUE(std::filesystem::exists(end)) << r.output;
      EXPECT_LE(max_position_difference(straight, end), kTolX) << integrator << ": " << first << " then " << second;
      // the state a restart reads; the eq. (54) bound is a max of sums taken in another order on the device
      const auto cs = io::read_checkpoint(straight).header.integrator_state, ce = io::read_checkpoint(end).header.integrator_state;
      for (const auto& [k, v] : cs.items())
        if (k != "dt_bound" && k != "predictor_ready") EXPECT_EQ(v, ce.at(k)) << k;
      if (cs.contains("dt_bound"))
        EXPECT_NEAR(cs["dt_bound"].get<double>(), ce.at("dt_bound").get<double>(), 1e-6 * cs["dt_bound"].get<double>());
    }
  }
}

TEST(DeviceRuns, BlowUpStopsLikeTheCpu) {
  const auto dir = test::scratch_dir("device_runs_blowup");
  // a density bound the dam break exceeds within a few steps, health.on_violation = "stop": exit 3, the last
  // good state written; the device's per-particle test finds the step, the host's rules word the message
  const std::string tight = kShort + " --set health.max_density_error=0.004 --set 'health.on_violation=\"stop\"'";
  const auto rc = test::run_command(exe() + " run " + q(kPaper) + " -o " + q(dir / "cpu") + tight);
  const auto rd = test::run_command(exe() + " run " + q(kPaper) + " -o " + q(dir / "dev") + tight + " --device cuda_emulation");
  ASSERT_EQ(rc.exit_code, 3) << rc.output;
  ASSERT_EQ(rd.exit_code, 3) << rd.output;
  // the same step, particle and value; only the rule's prefix and the run directory differ in the message
  const auto strip = [](std::string s, const std::string& d) {
    for (auto p = s.find(d); p != std::string::npos; p = s.find(d)) s.erase(p, d.size());
    const auto at = s.find("particle id");
    return at == std::string::npos ? s : s.substr(0, s.find(':')) + " ... " + s.substr(at);
  };
  EXPECT_EQ(strip(rc.output, (dir / "cpu").string()), strip(rd.output, (dir / "dev").string()));
  EXPECT_NE(rd.output.find("health rule 'density' (health.on_violation = \"stop\")"), std::string::npos) << rd.output;
  EXPECT_NE(rd.output.find("numerical failure at step"), std::string::npos) << rd.output;
  EXPECT_FALSE(io::list_checkpoints(dir / "dev" / "checkpoints").empty());
}

// The health rules' removals (health.on_violation = "remove", the default) on the device: a block thrown
// against the walls of a small box (tests/output/thrown_block.json) with bounds tightened so that all three
// rules fire (measured on the CPU: 15 'domain', 7 'density', 3 'speed'; the rate and total rules relaxed):
// the same particles at the same steps as on the CPU, the same diagnostics, the same survivors where they are.
TEST(DeviceRuns, RemovalRulesLikeTheCpu) {
  const auto dir = test::scratch_dir("device_runs_removal");
  const auto scene = test::source_dir() / "tests" / "output" / "thrown_block.json";
  const std::string sets = " --quiet --set health.max_density_error=0.01 --set health.max_mach=0.1"
                           " --set health.max_removed_fraction=1 --set health.max_removed_total=1";
  const auto rc = test::run_command(exe() + " run " + q(scene) + " -o " + q(dir / "cpu") + sets);
  const auto rd = test::run_command(exe() + " run " + q(scene) + " -o " + q(dir / "dev") + sets + " --device cuda_emulation");
  ASSERT_EQ(rc.exit_code, 0) << rc.output;
  ASSERT_EQ(rd.exit_code, 0) << rd.output;
  const auto ra = read_csv(dir / "cpu" / "removed.csv"), rb = read_csv(dir / "dev" / "removed.csv");
  std::map<std::string, int> rules;
  for (std::size_t r = 1; r < ra.size(); ++r) ++rules[ra[r].at(3)];
  for (const char* rule : {"domain", "density", "speed"})
    EXPECT_GT(rules[rule], 0) << "the CPU run removes particles by rule '" << rule << "' (else this test shows less)";
  ASSERT_EQ(ra.size(), rb.size());
  EXPECT_EQ(ra[0], rb[0]);
  for (std::size_t r = 1; r < ra.size(); ++r) {  // step, time, id, rule equal; the state values within round-off
    ASSERT_EQ(ra[r].size(), rb[r].size());
    for (std::size_t c = 0; c < ra[r].size(); ++c) {
      char* end = nullptr;
      const double x = std::strtod(ra[r][c].c_str(), &end);
      if (end == ra[r][c].c_str() || *end) {
        EXPECT_EQ(ra[r][c], rb[r][c]) << ra[0][c] << " row " << r;
        continue;
      }
      const double y = std::strtod(rb[r][c].c_str(), nullptr);
      EXPECT_LE(std::abs(x - y), kTolRel * std::max(1.0, std::abs(x))) << ra[0][c] << " row " << r;
    }
  }
  expect_same_table(dir / "cpu" / "diagnostics.csv", dir / "dev" / "diagnostics.csv", kTolRel);
  for (const char* ck : {"step_000000100.h5", "step_000000200.h5"}) {
    const auto a = dir / "cpu" / "checkpoints" / ck, b = dir / "dev" / "checkpoints" / ck;
    ASSERT_TRUE(std::filesystem::exists(b)) << b;
    EXPECT_LE(max_position_difference(a, b), 1e-9 * 0.02) << ck;  // thrown_block's spacing is 0.02 m
  }
}

TEST(DeviceRuns, CudaWithoutADeviceIsRefused) {
  const auto dir = test::scratch_dir("device_runs_no_gpu");
  const auto r = test::run_command(exe() + " run " + q(kPaper) + " -o " + q(dir / "run") + kShort + " --device cuda");
  std::string why;
  if (exec::cuda_device_present(&why)) {
    EXPECT_EQ(r.exit_code, 0) << r.output;  // a GPU machine runs it
    return;
  }
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("execution.device"), std::string::npos) << r.output;
  if (exec::cuda_compiled())
    EXPECT_NE(r.output.find("no CUDA device is present"), std::string::npos) << r.output;
  else
    EXPECT_NE(r.output.find("built without"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "run")) << "nothing is written when the device is refused";
  // an unknown device name is a scene error naming the key
  const auto u = test::run_command(exe() + " run " + q(kPaper) + " -o " + q(dir / "run2") + kShort + " --device tpu");
  EXPECT_EQ(u.exit_code, 2) << u.output;
  EXPECT_NE(u.output.find("execution.device"), std::string::npos) << u.output;
}
