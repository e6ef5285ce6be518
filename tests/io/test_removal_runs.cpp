// `varsph run` with particles removed by the health rules (sim/health.hpp): water thrown out through the
// top of the domain is removed and counted, the run goes on; a restart after removals is bitwise
// identical to a straight run; 1 and 2 threads remove the same particles; `varsph compare` matches the
// particles both runs still have.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "io/checkpoint.hpp"
#include "results_scenes.hpp"
#include "test_support.hpp"

using namespace varsph;
namespace fs = std::filesystem;

namespace {

std::string exe() { return test::varsph_exe().string(); }
std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

// A 0.1 x 0.2 m block (dx 0.02: 50 particles) thrown upward at 4 m/s in an open tank; the domain ends
// 0.02 m above the block, so its top rows leave through it from step ~80 on (dt 1e-4 s, 200 steps).
nlohmann::json thrown_block() {
  return nlohmann::json::parse(R"({
    "name": "thrown",
    "setup": "paper", "dimension": 2,
    "domain": {"min": [-0.1, -0.1], "max": [0.4, 0.22]},
    "particles": {"spacing": 0.02},
    "kernel": {"type": "gaussian", "h_over_dx": 1.2},
    "fluid": {"rho0": 1000.0, "c0": 40.0},
    "gravity": [0.0, -9.81],
    "bodies": [
      {"kind": "fluid", "shape": "box", "min": [0.1, 0.0], "max": [0.2, 0.2], "velocity": [0.0, 4.0]},
      {"kind": "boundary", "shape": "tank", "min": [0.0, 0.0], "max": [0.3, 0.2], "layers": 3}
    ],
    "physics": {"density": "continuity", "artificial_viscosity": {"alpha": 0.1, "beta": 0.0}},
    "boundary": {"model": "dynamic"},
    "integrator": {"type": "verlet", "dt": 0.0001},
    "time": {"end": 0.02},
    "output": {"every": 0.002, "precision": "float64"}
  })");
}

std::vector<std::string> lines(const fs::path& p) {
  std::vector<std::string> out;
  std::ifstream in(p);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> c;
  std::stringstream ss(line);
  for (std::string x; std::getline(ss, x, ',');) c.push_back(x);
  return c;
}

// diagnostics rows without the wall_seconds column
std::vector<std::string> diag_without_wall(const fs::path& p) {
  std::vector<std::string> out;
  for (const auto& l : lines(p)) {
    auto c = cells(l);
    if (c.size() > 14) c.erase(c.begin() + 14);
    std::string j;
    for (const auto& x : c) j += x + ",";
    out.push_back(j);
  }
  return out;
}

void expect_same_arrays(const fs::path& a, const fs::path& b) {
  const auto ca = io::read_checkpoint(a), cb = io::read_checkpoint(b);
  EXPECT_EQ(ca.header.particles, cb.header.particles);
  EXPECT_EQ(ca.header.time, cb.header.time);
  ASSERT_EQ(ca.arrays.size(), cb.arrays.size());
  for (std::size_t k = 0; k < ca.arrays.size(); ++k)
    EXPECT_TRUE(ca.arrays[k].bytes == cb.arrays[k].bytes) << a << " vs " << b << ": field " << ca.arrays[k].name;
}

}  // namespace

TEST(RemovalRuns, WaterLeavingTheDomainIsRemovedCountedAndTheRunGoesOn) {
  const auto dir = test::scratch_dir("removal_counts");
  const auto scene = test::write_scene(dir, thrown_block());
  const auto run = dir / "run";
  const auto r = test::run_command(exe() + " run " + q(scene) + " -o " + q(run));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // the first removal is reported once, the summary counts them per rule
  EXPECT_NE(r.output.find("warning: step"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("health rule 'domain'"), std::string::npos) << r.output;
  const auto at = r.output.find("; removed ");
  ASSERT_NE(at, std::string::npos) << r.output;
  const long removed = std::stol(r.output.substr(at + 10));
  EXPECT_GE(removed, 5) << "at least the top row (5 particles) leaves by t = 0.02 s";
  EXPECT_NE(r.output.find("of 50 fluid particles (domain " + std::to_string(removed) + ", density 0, speed 0"),
            std::string::npos)
      << r.output;
  // removed.csv: one row per particle, above the domain top when removed, with its id and rule
  const auto rem = lines(run / "removed.csv");
  ASSERT_EQ(long(rem.size()), removed + 1);
  EXPECT_EQ(rem[0], "time,step,id,rule,x,y,z,vx,vy,vz,density,pressure,fluid_neighbours,boundary_neighbours");
  for (std::size_t k = 1; k < rem.size(); ++k) {
    const auto c = cells(rem[k]);
    EXPECT_EQ(c[3], "domain");
    EXPECT_GT(std::stod(c[5]), 0.22);
  }
  // diagnostics.csv: the new columns are appended; counts are cumulative and match the particle count
  const auto diag = lines(run / "diagnostics.csv");
  const auto head = cells(diag[0]);
  // then `imbalance` (runs on several MPI ranks, docs/parallel.md) and the open-boundary flows (issue 32)
  ASSERT_EQ(head.size(), 37u);  // ... then the rigid bodies' five (issue 30)
  EXPECT_EQ(head[19], "dt_bound");
  EXPECT_EQ(head[20], "fluid_particles");
  EXPECT_EQ(head[21], "removed_domain");
  EXPECT_EQ(head[22], "removed_density");
  EXPECT_EQ(head[23], "removed_speed");
  EXPECT_EQ(head[24], "imbalance");
  EXPECT_EQ(head[25], "particles_created");
  EXPECT_EQ(head[31], "mass_balance");
  EXPECT_EQ(head[36], "bodies_potential_energy");
  long last_removed = 0;
  for (std::size_t k = 1; k < diag.size(); ++k) {
    const auto c = cells(diag[k]);
    const long n = std::stol(c[20]), rd = std::stol(c[21]);
    EXPECT_EQ(n + rd, 50) << diag[k];
    // the mass balance counts the health removals as mass out: closed to round-off (issue 32)
    EXPECT_LE(std::abs(std::stod(c[31])), 1e-12 * std::stod(c[30]) * 50) << diag[k];
    if (rd > 0) EXPECT_GT(std::stod(c[29]), 0) << diag[k];
    EXPECT_GE(rd, last_removed);
    last_removed = rd;
  }
  EXPECT_EQ(last_removed, removed);
  const auto j = nlohmann::json::parse(test::read_text(run / "run.json"));
  EXPECT_EQ(j.at("health").at("removed").at("domain").get<long>(), removed);
  EXPECT_EQ(j.at("health").at("fluid_particles_initial").get<long>(), 50);
  EXPECT_EQ(j.at("resolved").at("fluid_particles").get<long>(), 50 - removed);
  // with health.on_violation = "stop" the same run is a blow-up naming the rule
  const auto s = test::run_command(exe() + " run " + q(scene) + " -o " + q(dir / "strict") +
                                   " --set health.on_violation=stop");
  EXPECT_EQ(s.exit_code, 3) << s.output;
  EXPECT_NE(s.output.find("health rule 'domain' (health.on_violation = \"stop\"): particle id"), std::string::npos)
      << s.output;
}

// 200 steps straight vs 100 + restart in the run's own directory + 100: removals happen before and after
// the checkpoint (the restart reads fewer particles than the scene builds).
TEST(RemovalRuns, RestartAfterRemovalsIsBitwiseIdentical) {
  const auto dir = test::scratch_dir("removal_restart");
  const auto scene = test::write_scene(dir, thrown_block());
  const auto straight = dir / "straight", split = dir / "split";
  auto r = test::run_command(exe() + " run " + q(scene) + " -o " + q(straight) + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::run_command(exe() + " run " + q(scene) + " -o " + q(split) + " --quiet --set time.end=0.01");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto ckpt = split / "checkpoints" / "step_000000100.h5";
  const auto c100 = io::read_checkpoint(ckpt);
  const auto at100 = nlohmann::json::parse(test::read_text(split / "run.json"));
  ASSERT_LT(at100.at("resolved").at("fluid_particles").get<long>(), 50)
      << "no removal before the checkpoint: the test would not test it";
  r = test::run_command(exe() + " run " + q(scene) + " --restart " + q(ckpt) + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_same_arrays(straight / "checkpoints" / "step_000000200.h5", split / "checkpoints" / "step_000000200.h5");
  const auto c200 = io::read_checkpoint(straight / "checkpoints" / "step_000000200.h5");
  EXPECT_LT(c200.header.particles, c100.header.particles) << "no removal after the checkpoint";
  EXPECT_EQ(diag_without_wall(straight / "diagnostics.csv"), diag_without_wall(split / "diagnostics.csv"));
  EXPECT_EQ(test::read_text(straight / "removed.csv"), test::read_text(split / "removed.csv"));
}

TEST(RemovalRuns, OneAndTwoThreadsRemoveTheSameParticles) {
  const auto dir = test::scratch_dir("removal_threads");
  const auto scene = test::write_scene(dir, thrown_block());
  for (const char* t : {"1", "2"}) {
    const auto r = test::run_command(exe() + " run " + q(scene) + " -o " + q(dir / (std::string("t") + t)) +
                                     " --quiet --threads " + t);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  expect_same_arrays(dir / "t1" / "checkpoints" / "step_000000200.h5", dir / "t2" / "checkpoints" / "step_000000200.h5");
  EXPECT_EQ(test::read_text(dir / "t1" / "removed.csv"), test::read_text(dir / "t2" / "removed.csv"));
  EXPECT_GT(lines(dir / "t1" / "removed.csv").size(), 1u);
}

TEST(RemovalRuns, CompareMatchesTheParticlesBothRunsHaveAndSaysWhatIsMissing) {
  const auto dir = test::scratch_dir("removal_compare");
  const auto scene = test::write_scene(dir, thrown_block());
  auto r = test::run_command(exe() + " run " + q(scene) + " -o " + q(dir / "a") + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // the same run in a taller domain: nothing leaves, and the particles both have move identically
  // until the first removal (a removed particle no longer pushes its neighbours)
  r = test::run_command(exe() + " run " + q(scene) + " -o " + q(dir / "b") + " --quiet --set 'domain.max=[0.4, 0.6]'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::run_command(exe() + " compare " + q(dir / "a") + " " + q(dir / "b") + " -o " + q(dir / "ab"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("only in"), std::string::npos) << r.output;
  const auto rows = lines(dir / "ab" / "deviation.csv");
  ASSERT_GT(rows.size(), 2u);
  EXPECT_EQ(rows[0], "time,D_max,D_mean,D_rms,matched,only_a,only_b");
  const auto first = cells(rows[1]), last = cells(rows.back());
  EXPECT_EQ(first[4], "50");
  EXPECT_EQ(first[5], "0");
  EXPECT_EQ(first[6], "0");
  EXPECT_EQ(std::stol(last[4]) + std::stol(last[6]), 50) << rows.back();
  EXPECT_GT(std::stol(last[6]), 0) << rows.back();
  EXPECT_EQ(last[5], "0");
}
