#pragma once
// Bitwise checks of a growing and shrinking store (open boundaries), shared by the open-boundary tests of each
// integrator: 1 and 2 threads, and a checkpoint restart in the same process, give the same state bits.
#include <gtest/gtest.h>
#include <omp.h>
#include <unistd.h>

#include <cstddef>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/checkpoint.hpp"
#include "scene/scene.hpp"
#include "sim/restart.hpp"
#include "sim/simulation.hpp"

namespace varsph::test {

// The bytes of the named per-particle fields, in store order.
inline std::vector<std::byte> state_bytes(const Simulation<2>& sim, const std::set<std::string>& fields) {
  std::vector<std::byte> out;
  for (const auto& f : sim.store().fields()) {
    if (!fields.count(f->name())) continue;
    const auto* p = static_cast<const std::byte*>(f->raw());
    out.insert(out.end(), p, p + f->bytes_per_particle() * sim.size());
  }
  return out;
}

// 120 steps on 1 and on 2 threads give the same bits, with particles created on the way.
inline void expect_open_threads_bitwise(const scene::Scene& scene, const std::set<std::string>& fields) {
  const int before = omp_get_max_threads();
  std::vector<std::byte> a, b;
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    Simulation<2> sim(scene);
    for (int s = 0; s < 120; ++s) sim.advance();
    (threads == 1 ? a : b) = state_bytes(sim, fields);
    EXPECT_GT(sim.flow().created, 0);
  }
  omp_set_num_threads(before);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(a == b);
}

// 160 steps straight against 80 steps, a checkpoint, and 80 steps of a new simulation restored from it.
inline void expect_open_restart_bitwise(const scene::Scene& scene, const std::set<std::string>& fields,
                                        const std::string& tag) {
  const auto dir = std::filesystem::temp_directory_path() / ("varsph_" + tag + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / "step.h5";
  Simulation<2> a(scene);
  for (int s = 0; s < 80; ++s) a.advance();
  io::write_checkpoint(path, checkpoint_header(a, nlohmann::json::object()), a.store());
  for (int s = 0; s < 80; ++s) a.advance();
  Simulation<2> b(scene);
  restore_from_checkpoint(b, io::read_checkpoint(path), path.string());
  for (int s = 0; s < 80; ++s) b.advance();
  EXPECT_GT(a.flow().created, 0);
  EXPECT_EQ(a.next_id(), b.next_id());
  EXPECT_EQ(a.flow().created, b.flow().created);
  EXPECT_EQ(a.flow().mass_in, b.flow().mass_in);
  EXPECT_EQ(a.time(), b.time());
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(state_bytes(a, fields) == state_bytes(b, fields));
  std::filesystem::remove_all(dir);
}

}  // namespace varsph::test
