#pragma once
// Helpers of the multi-rank tests: launching `varsph` under mpirun, comparing the particle states of two
// runs (their final checkpoints, particles matched by id, every checkpointed field compared bit for
// bit) and their tables.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/checkpoint.hpp"
#include "test_support.hpp"

namespace varsph::test {

// "mpirun --allow-run-as-root --oversubscribe -n N " (the flags CMake found for this MPI).
inline std::string mpirun(int n) {
  return std::string(VARSPH_MPIEXEC) + " " + VARSPH_MPIEXEC_FLAGS + " -n " + std::to_string(n) + " ";
}

// `varsph run SCENE -o DIR --overwrite --quiet ARGS` on n ranks (n = 0: the serial program, no mpirun).
inline CommandResult run_varsph(int n, const std::filesystem::path& scene, const std::filesystem::path& out,
                                const std::string& args = "") {
  const std::string cmd = (n > 0 ? mpirun(n) : std::string()) + varsph_exe().string() + " run " + scene.string() +
                          " -o " + out.string() + " --overwrite --quiet " + args;
  return run_command(cmd);
}

inline std::filesystem::path last_checkpoint(const std::filesystem::path& run) {
  const auto all = io::list_checkpoints(run / "checkpoints");
  return all.empty() ? std::filesystem::path() : all.back().second;
}

struct StateDiff {
  std::int64_t particles = 0;
  int fields = 0;                  // checkpointed fields compared
  std::int64_t differing = 0;      // values that are not bitwise equal
  double max_abs = 0;              // largest |a - b| over floating-point values
  std::string first;               // the first difference, for the message
  bool same_header = true;         // step, time, dt and integrator state equal
};

inline std::int64_t id_at(const io::CheckpointArray& ids, std::size_t i) {
  std::int64_t v;
  std::memcpy(&v, ids.bytes.data() + i * sizeof v, sizeof v);
  return v;
}

// Two checkpoints (single files or manifests with pieces), particles matched by id.
inline StateDiff compare_states(const std::filesystem::path& a, const std::filesystem::path& b) {
  const io::Checkpoint ca = io::read_checkpoint(a), cb = io::read_checkpoint(b);
  StateDiff d;
  const auto& ha = ca.header;
  const auto& hb = cb.header;
  d.same_header = ha.step == hb.step && ha.time == hb.time && ha.dt == hb.dt && ha.particles == hb.particles &&
                  ha.integrator_state == hb.integrator_state;
  d.particles = ha.particles;
  if (ha.particles != hb.particles) {
    d.differing = 1;
    d.first = "particle counts differ";
    return d;
  }
  const io::CheckpointArray* ida = ca.find("id");
  const io::CheckpointArray* idb = cb.find("id");
  std::map<std::int64_t, std::size_t> row_b;
  for (std::size_t i = 0; i < std::size_t(hb.particles); ++i) row_b[id_at(*idb, i)] = i;
  for (const auto& arr : ca.arrays) {
    const io::CheckpointArray* other = cb.find(arr.name);
    if (!other) continue;
    ++d.fields;
    const std::size_t n = std::size_t(ha.particles), width = arr.bytes.size() / std::max<std::size_t>(n, 1);
    const std::size_t scalar = width / std::size_t(arr.components);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = row_b.at(id_at(*ida, i));
      const std::byte* pa = arr.bytes.data() + i * width;
      const std::byte* pb = other->bytes.data() + j * width;
      if (std::memcmp(pa, pb, width) == 0) continue;
      for (int c = 0; c < arr.components; ++c) {
        double va = 0, vb = 0;
        if (arr.type == ScalarType::Float64) {
          std::memcpy(&va, pa + std::size_t(c) * scalar, 8);
          std::memcpy(&vb, pb + std::size_t(c) * scalar, 8);
        } else if (arr.type == ScalarType::Float32) {
          float fa, fb;
          std::memcpy(&fa, pa + std::size_t(c) * scalar, 4);
          std::memcpy(&fb, pb + std::size_t(c) * scalar, 4);
          va = fa;
          vb = fb;
        }
        if (std::memcmp(pa + std::size_t(c) * scalar, pb + std::size_t(c) * scalar, scalar) == 0) continue;
        ++d.differing;
        d.max_abs = std::max(d.max_abs, std::abs(va - vb));
        if (d.first.empty()) {
          std::ostringstream o;
          o.precision(17);
          o << arr.name << "[" << c << "] of id " << id_at(*ida, i) << ": " << va << " vs " << vb;
          d.first = o.str();
        }
      }
    }
  }
  return d;
}

// A CSV table: header and rows of cells.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  int column(const std::string& name) const {
    for (std::size_t k = 0; k < header.size(); ++k)
      if (header[k] == name) return int(k);
    return -1;
  }
  double value(std::size_t row, const std::string& name) const {
    const int c = column(name);
    return c < 0 || rows[row][std::size_t(c)].empty() ? std::nan("") : std::stod(rows[row][std::size_t(c)]);
  }
};

inline Csv read_csv(const std::filesystem::path& p) {
  Csv t;
  std::ifstream in(p);
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    if (!line.empty() && line.back() == ',') cells.push_back("");
    if (first) t.header = cells;
    else t.rows.push_back(cells);
    first = false;
  }
  return t;
}

// diagnostics.csv and probes.csv of a run on `ranks` ranks against the serial run: maxima of equal states
// exactly, sums over ranks (energies, momenta, probes) to round-off.
inline void expect_same_tables(const std::filesystem::path& serial, const std::filesystem::path& run, int ranks) {
  const Csv a = read_csv(serial / "diagnostics.csv"), b = read_csv(run / "diagnostics.csv");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  // imbalance, then the open-boundary and mass-balance columns appended after it (issue 32), then the
  // rigid bodies' five (issue 30)
  ASSERT_GE(b.header.size(), 13u);
  ASSERT_EQ(b.header[b.header.size() - 13], "imbalance");
  ASSERT_EQ(b.header[b.header.size() - 6], "mass_balance");
  ASSERT_EQ(b.header.back(), "bodies_potential_energy");
  for (std::size_t r = 0; r < a.rows.size(); ++r) {
    for (const char* exact : {"frame", "step", "time", "dt", "max_speed", "density_error_max"})
      EXPECT_EQ(a.value(r, exact), b.value(r, exact)) << exact << ", row " << r;  // maxima of equal states
    // sums over ranks are added in another order: equal to round-off (1e-12 of the sum of magnitudes)
    const double scale = std::abs(a.value(r, "kinetic_energy")) + std::abs(a.value(r, "potential_energy")) +
                         std::abs(a.value(r, "internal_energy")) + 1e-300;
    for (const char* sum : {"kinetic_energy", "potential_energy", "internal_energy"})
      EXPECT_NEAR(a.value(r, sum), b.value(r, sum), 1e-12 * scale) << sum << ", row " << r;
    for (const char* m : {"momentum_x", "momentum_y"})
      EXPECT_NEAR(a.value(r, m), b.value(r, m), 1e-12 * (1 + std::abs(a.value(r, m)))) << m << ", row " << r;
    EXPECT_GE(b.value(r, "imbalance"), 1.0);
    EXPECT_EQ(a.value(r, "imbalance"), 1.0);
  }
  const Csv pa = read_csv(serial / "probes.csv"), pb = read_csv(run / "probes.csv");
  ASSERT_EQ(pa.rows.size(), pb.rows.size());
  ASSERT_EQ(pa.header, pb.header);
  for (std::size_t r = 0; r < pa.rows.size(); ++r)
    for (const auto& c : pa.header) {
      const double x = pa.value(r, c), y = pb.value(r, c);
      EXPECT_NEAR(x, y, 1e-10 * (1 + std::abs(x))) << "probes.csv " << c << ", row " << r << ", " << ranks << " ranks";
    }
}

}  // namespace varsph::test
