// The fast-tier share of the multi-rank tests (a few seconds): a small 2D dam break with probes on 2 and 3
// ranks gives the particle states of one process bit for bit after 200 steps, the outputs a user opens
// (one .pvd of .pvtu frames, diagnostics.csv, probes.csv, run.json), and a checkpoint written by 2 ranks
// restarts on 3 ranks and in the serial program to the same bits. The larger cases are in
// test_mpi_runs.cpp (label mpi).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "mpi_support.hpp"
#include "results_scenes.hpp"

namespace varsph::test {
namespace {

TEST(MpiQuick, TinyDamBreakOnTwoAndThreeRanksEqualsOneProcessBitwise) {
  const auto dir = scratch_dir("mpi_quick_dam");
  const auto scene = write_scene(dir, tiny_dam_break());
  const auto serial = run_varsph(0, scene, dir / "serial");
  ASSERT_EQ(serial.exit_code, 0) << serial.output;
  for (int n : {2, 3}) {
    const auto out = dir / ("ranks" + std::to_string(n));
    const auto r = run_varsph(n, scene, out);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const StateDiff d = compare_states(last_checkpoint(dir / "serial"), last_checkpoint(out));
    EXPECT_TRUE(d.same_header);
    EXPECT_GT(d.particles, 200);
    EXPECT_GE(d.fields, 9);  // position, velocity, density, pressure, mass, kind, id, normal, body
    EXPECT_EQ(d.differing, 0) << n << " ranks: " << d.first << " (max |diff| " << d.max_abs << ")";
    // what a user opens: one .pvd listing .pvtu frames, each with one piece per rank
    const std::string pvd = read_text(out / "tiny.pvd");
    EXPECT_NE(pvd.find("frames/tiny_000010.pvtu"), std::string::npos) << pvd;
    EXPECT_EQ(pvd.find(".vtu\""), std::string::npos);
    const std::string pvtu = read_text(out / "frames" / "tiny_000010.pvtu");
    for (int k = 0; k < n; ++k) {
      const std::string piece = "tiny_000010/tiny_000010_" + std::to_string(k) + ".vtu";
      EXPECT_NE(pvtu.find("Source=\"" + piece + "\""), std::string::npos) << pvtu;
      EXPECT_TRUE(std::filesystem::exists(out / "frames" / piece));
    }
    expect_same_tables(dir / "serial", out, n);
    const auto run_json = nlohmann::json::parse(read_text(out / "run.json"));
    EXPECT_EQ(run_json.at("parallel").at("ranks").get<int>(), n);
    EXPECT_EQ(run_json.at("status").get<std::string>(), "completed");
    EXPECT_EQ(run_json.at("resolved").at("fluid_particles"),
              nlohmann::json::parse(read_text(dir / "serial" / "run.json")).at("resolved").at("fluid_particles"));
  }
}

TEST(MpiQuick, CheckpointOfTwoRanksRestartsOnThreeRanksAndInOneProcess) {
  const auto dir = scratch_dir("mpi_quick_restart");
  const auto scene = write_scene(dir, tiny_dam_break());
  ASSERT_EQ(run_varsph(0, scene, dir / "straight").exit_code, 0);
  const auto two = run_varsph(2, scene, dir / "two", "--set checkpoint.every_steps=100");
  ASSERT_EQ(two.exit_code, 0) << two.output;
  const auto ckpt = dir / "two" / "checkpoints" / "step_000000100.h5";
  ASSERT_TRUE(std::filesystem::exists(ckpt));
  EXPECT_TRUE(std::filesystem::exists(dir / "two" / "checkpoints" / "step_000000100" / "piece_000001.h5"));
  const auto three = run_command(mpirun(3) + varsph_exe().string() + " run " + scene.string() + " --restart " +
                                 ckpt.string() + " -o " + (dir / "three").string() + " --quiet");
  ASSERT_EQ(three.exit_code, 0) << three.output;
  const auto one = run_command(varsph_exe().string() + " run " + scene.string() + " --restart " + ckpt.string() +
                               " -o " + (dir / "one").string() + " --quiet");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  for (const char* run : {"three", "one", "two"}) {
    const StateDiff d = compare_states(last_checkpoint(dir / "straight"), last_checkpoint(dir / run));
    EXPECT_TRUE(d.same_header) << run;
    EXPECT_EQ(d.differing, 0) << run << ": " << d.first << " (max |diff| " << d.max_abs << ")";
  }
}

// Antuono's delta-SPH reads its neighbours' renormalised density gradients, which ghosts get from their
// owners after the gradient sweep (Rates::refresh_ghosts). Without that exchange this case differed from
// one process by D = 2.1e-5 m on 2 ranks after 200 steps; the label-mpi test covers more (MpiRuns.Antuono*).
TEST(MpiQuick, TinyDamBreakWithAntuonoDeltaSphOnTwoRanksEqualsOneProcessBitwise) {
  const auto dir = scratch_dir("mpi_quick_antuono");
  nlohmann::json j = tiny_dam_break();
  j["physics"]["density_diffusion"] = {{"type", "antuono"}, {"delta", 0.1}};
  j.erase("probes");
  const auto scene = write_scene(dir, j);
  const auto serial = run_varsph(0, scene, dir / "serial");
  ASSERT_EQ(serial.exit_code, 0) << serial.output;
  const auto r = run_varsph(2, scene, dir / "ranks2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const StateDiff d = compare_states(last_checkpoint(dir / "serial"), last_checkpoint(dir / "ranks2"));
  EXPECT_TRUE(d.same_header);
  EXPECT_GT(d.particles, 200);
  EXPECT_EQ(d.differing, 0) << d.first << " (max |diff| " << d.max_abs << ")";
}

// What several ranks cannot run yet is refused before any step, with the serial exit code for bad input
// and one message naming the key, agreed by every rank (no MPI_Abort).
TEST(MpiQuick, MdbcWallsAreRefusedOnTwoRanksWithExitTwoAndOneMessage) {
  const auto dir = scratch_dir("mpi_quick_mdbc");
  const auto scene = write_scene(dir, tiny_dam_break());
  const auto r = run_varsph(2, scene, dir / "out", "--set boundary.model=\\\"mdbc\\\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  std::size_t count = 0;
  for (std::size_t at = 0; (at = r.output.find("varsph: error:", at)) != std::string::npos; ++at) ++count;
  EXPECT_EQ(count, 1u) << r.output;
  EXPECT_NE(r.output.find("boundary.model = \"mdbc\" is not available on several MPI ranks"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("MPI_ABORT"), std::string::npos) << r.output;
}

// The film of pipelines/open/film_slope.json made small (dx 1 mm, 50 mm long): a free-surface inlet and an outlet.
nlohmann::json small_film() {
  nlohmann::json j = nlohmann::json::parse(test::read_text(source_dir() / "pipelines/open/film_slope.json"));
  j["particles"]["spacing"] = 0.001;
  j["domain"] = {{"min", {-0.008, -0.008}}, {"max", {0.06, 0.03}}};
  j["bodies"][0]["max"] = {0.05, 0.01};
  j["bodies"][1]["min"] = {-0.004, 0.0};
  j["bodies"][1]["max"] = {0.054, 0.02};
  j["open_boundaries"][0]["min"] = {-0.004, 0.0};
  j["open_boundaries"][1]["min"] = {0.05, 0.0};
  j["open_boundaries"][1]["max"] = {0.054, 0.02};
  return j;
}

// Runs `scene` in one process (dir/serial) and on 2 ranks (dir/ranks2): every particle's state bit for bit (at
// least `min_particles` of them) and the open boundaries' flows of diagnostics.csv exactly, row by row.
void expect_two_ranks_equal_one_process(const std::filesystem::path& scene, const std::filesystem::path& dir,
                                        const std::string& args, std::int64_t min_particles) {
  const auto serial = run_varsph(0, scene, dir / "serial", args);
  ASSERT_EQ(serial.exit_code, 0) << serial.output;
  const auto r = run_varsph(2, scene, dir / "ranks2", args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const StateDiff d = compare_states(last_checkpoint(dir / "serial"), last_checkpoint(dir / "ranks2"));
  EXPECT_TRUE(d.same_header);
  EXPECT_GT(d.particles, min_particles);
  EXPECT_EQ(d.differing, 0) << d.first << " (max |diff| " << d.max_abs << ")";
  const Csv a = read_csv(dir / "serial" / "diagnostics.csv"), b = read_csv(dir / "ranks2" / "diagnostics.csv");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t row = 0; row < a.rows.size(); ++row)
    for (const char* exact : {"fluid_particles", "particles_created", "removed_outlet", "buffer_particles", "mass_in",
                              "mass_out"})
      EXPECT_EQ(a.value(row, exact), b.value(row, exact)) << exact << ", row " << row;
}

// issue 32: open boundaries on several ranks. The Poiseuille channel with an inlet and an outlet for 0.3 s (667
// steps, particles created and removed, buffer particles whose ghost nodes lie on another rank): one process's
// particle states bit for bit (ids of created particles included), and the flows of diagnostics.csv exactly.
TEST(MpiQuick, OpenBoundariesOnTwoRanksEqualOneProcessBitwise) {
  const auto dir = scratch_dir("mpi_quick_open");
  const auto scene = write_scene(dir, nlohmann::json::parse(test::read_text(source_dir() / "pipelines/open/channel_poiseuille.json")));
  const std::string args = "--set time.end=0.3 --set output.every=0.1 --set output.precision=\\\"float64\\\"";
  ASSERT_NO_FATAL_FAILURE(expect_two_ranks_equal_one_process(scene, dir, args, 1000));
  const Csv a = read_csv(dir / "serial" / "diagnostics.csv");
  EXPECT_GT(a.value(a.rows.size() - 1, "particles_created"), 0);
}

// The same channel under the variational integrator (pipelines/open/channel_poiseuille_variational.json): buffer
// particles held through the fixed point (every iterate's convergence test over both ranks), particles created and
// removed after each accepted step: one process's bits and flows on 2 ranks.
TEST(MpiQuick, OpenBoundariesWithTheVariationalIntegratorOnTwoRanksEqualOneProcessBitwise) {
  const auto dir = scratch_dir("mpi_quick_open_variational");
  const auto scene =
      write_scene(dir, nlohmann::json::parse(test::read_text(source_dir() / "pipelines/open/channel_poiseuille_variational.json")));
  const std::string args = "--set time.end=0.3 --set output.every=0.1 --set output.precision=\\\"float64\\\"";
  ASSERT_NO_FATAL_FAILURE(expect_two_ranks_equal_one_process(scene, dir, args, 1000));
  const Csv a = read_csv(dir / "serial" / "diagnostics.csv");
  EXPECT_GT(a.value(a.rows.size() - 1, "particles_created"), 0);
  EXPECT_GT(a.value(a.rows.size() - 1, "removed_outlet"), 0);
  EXPECT_GT(a.value(a.rows.size() - 1, "fp_iterations_mean"), 1.0);  // the fixed point iterated
}

// A free-surface inlet (a fixed water level, hydrostatic density, docs/open_boundaries.md) and an outlet on a
// free-surface film: 2 ranks give one process's bits, flows and created ids included (the level is a filter on
// creation decided per particle). The small film above.
TEST(MpiQuick, FreeSurfaceInletOnTwoRanksEqualsOneProcessBitwise) {
  const auto dir = scratch_dir("mpi_quick_film");
  nlohmann::json j = small_film();
  const auto scene = write_scene(dir, j);
  const std::string args = "--set time.end=0.08 --set output.every=0.04 --set output.precision=\\\"float64\\\"";
  ASSERT_NO_FATAL_FAILURE(expect_two_ranks_equal_one_process(scene, dir, args, 500));
  const Csv a = read_csv(dir / "serial" / "diagnostics.csv");
  EXPECT_GT(a.value(a.rows.size() - 1, "particles_created"), 0);
  EXPECT_GT(a.value(a.rows.size() - 1, "removed_outlet"), 0);
}

// A free-surface inlet whose water level varies in time (`water_level.file`: it rises 4 spacings, then falls 3):
// 2 ranks give one process's bits and flows. The rows that become wet are listed alike on every rank and created
// by the rank that owns one process's source particle (the smallest order tag), with one process's ids and tags
// after the step's copies (OpenBoundaries::fill_risen_rows); rows above a falling level leave per particle.
TEST(MpiQuick, VaryingWaterLevelOnTwoRanksEqualsOneProcessBitwise) {
  const auto dir = scratch_dir("mpi_quick_film_level");
  nlohmann::json j = small_film();
  j["open_boundaries"][0]["water_level"] = {{"file", "level.csv"}};
  std::filesystem::create_directories(dir);
  {
    std::ofstream csv(dir / "level.csv");
    csv << "time,level\n0,0.01\n0.04,0.014\n0.08,0.011\n";
  }
  const auto scene = write_scene(dir, j);
  const std::string args = "--set time.end=0.08 --set output.every=0.02 --set output.precision=\\\"float64\\\"";
  ASSERT_NO_FATAL_FAILURE(expect_two_ranks_equal_one_process(scene, dir, args, 500));
  const Csv a = read_csv(dir / "serial" / "diagnostics.csv");
  // the inlet's buffer follows the level: 4 columns x the rows below it (10 at t = 0, 14 at 0.04 s, 11 at
  // 0.08 s); the outlet's buffer (the column's count, about 40) moves by a few particles as the film passes
  const std::size_t last = a.rows.size() - 1;
  double peak = 0;
  for (std::size_t row = 0; row < a.rows.size(); ++row) peak = std::max(peak, a.value(row, "buffer_particles"));
  EXPECT_NEAR(peak - a.value(0, "buffer_particles"), 16.0, 4.0);
  EXPECT_NEAR(peak - a.value(last, "buffer_particles"), 12.0, 4.0);
  EXPECT_GT(a.value(last, "particles_created"), 0);
}

}  // namespace
}  // namespace varsph::test
