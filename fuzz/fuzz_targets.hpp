#pragma once
// What each libFuzzer harness does with one input, shared with the fast-tier regression test
// (tests/fuzz/), which replays fuzz/regressions/ through the same functions in the normal build.
// Each function returns true when the input was accepted and false when it was refused with the
// documented error (InputError / GeometryError: exit 2 in the solver); anything else escapes.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "io/checkpoint.hpp"
#include "scene/scene.hpp"
#include "sim/particle_budget.hpp"
#include "varsph/geometry/geometry_error.h"
#include "varsph/geometry/read_mesh.h"
#include "varsph/geometry/sample_body.h"

namespace varsph::fuzz {

// The readers under test take paths, as the command line does: the input goes to a scratch file named
// by process id (parallel fuzzing jobs do not collide), in $VARSPH_FUZZ_TMP, else /dev/shm (memory), else
// /tmp. Each input is written as a new file (the old one removed first): on ext4, truncating and
// rewriting one file forces a flush at close (auto_da_alloc), which made the harnesses I/O-bound; on
// tmpfs the scene harness ran 2.8x faster (docs/reliability.md, "Fuzzing").
inline std::filesystem::path scratch_dir() {
  if (const char* dir = std::getenv("VARSPH_FUZZ_TMP")) return dir;
  std::error_code ec;
  if (std::filesystem::is_directory("/dev/shm", ec) && ::access("/dev/shm", W_OK) == 0) return "/dev/shm";
  return "/tmp";
}

inline std::filesystem::path scratch_file(const std::string& ext) {
  return scratch_dir() / ("varsph_fuzz_" + std::to_string(::getpid()) + ext);
}

inline void write_file(const std::filesystem::path& p, const std::uint8_t* data, std::size_t size) {
  ::unlink(p.c_str());  // a new file, not a truncated one (see scratch_dir)
  std::FILE* f = std::fopen(p.c_str(), "wb");
  if (!f) std::abort();
  if (size) std::fwrite(data, 1, size, f);
  std::fclose(f);
}

// A scene file, optionally followed by a line "#--set" and one KEY=VALUE override per line (at most 16,
// empty lines skipped).
inline bool run_scene(const std::uint8_t* data, std::size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> overrides;
  if (const auto cut = text.find("\n#--set\n"); cut != std::string::npos) {
    const std::string rest = text.substr(cut + 8);
    text.resize(cut + 1);
    std::size_t start = 0;
    while (overrides.size() < 16) {
      const auto end = rest.find('\n', start);
      std::string line = rest.substr(start, end == std::string::npos ? std::string::npos : end - start);
      if (!line.empty()) overrides.push_back(std::move(line));
      if (end == std::string::npos) break;
      start = end + 1;
    }
  }
  static const auto path = scratch_file(".json");
  write_file(path, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
  try {
    const scene::Scene s = scene::parse_scene(path, overrides);
    check_particle_budget(s);  // the estimate runs on every scene that parses
    return true;
  } catch (const InputError&) {
    return false;
  }
}

// One mesh file of extension `ext` through the geometry module's entry point, as a scene body uses it:
// surface fill with 2 layers, volume fill, and for 3D formats a 2D section; dx = 0.25 m in a domain of
// +-10 m with a budget of 2000 particles (larger estimates are refused before sampling). Returns true
// when any of the three was sampled.
inline bool run_mesh(const std::string& ext, const std::uint8_t* data, std::size_t size) {
  static const auto path = scratch_file(ext);
  write_file(path, data, size);
  const bool poly2d = ext == ".poly2d";
  const int dim = poly2d ? 2 : 3;
  geometry::BodyRequest r;
  r.mesh = path;
  r.dimension = dim;
  r.spacing = 0.25;
  r.max_particles = 2000;
  r.domain_min = Eigen::VectorXd::Constant(dim, -10.0);
  r.domain_max = Eigen::VectorXd::Constant(dim, 10.0);
  r.layers = 2;
  bool any = false;
  auto sample = [&] {
    try {
      (void)geometry::sample_body(r);
      any = true;
    } catch (const geometry::GeometryError&) {
    }
  };
  sample();
  r.fill = "volume";
  r.layers = 1;
  sample();
  if (!poly2d) {
    r.dimension = 2;
    r.fill = "surface";
    r.domain_min = Eigen::VectorXd::Constant(2, -10.0);
    r.domain_max = Eigen::VectorXd::Constant(2, 10.0);
    r.section_point = Eigen::Vector3d(0.3, 0.3, 0.3);
    sample();
  }
  return any;
}

// One mesh file through its reader alone: the format's parser, our checks before allocation and the
// repairs (read_mesh with the self-intersection test), no sampling. For STL, OBJ, OFF and PLY (the
// .poly2d reader is a few lines; fuzz_poly2d already runs at ~300 inputs/s). The
// readers are where hostile bytes meet the code; without the samplers an input costs about 1/13 of
// run_mesh (0.55 against 7.4 ms per STL corpus file in release), so these harnesses reach 10^6
// executions where run_mesh's cannot (docs/reliability.md, "Fuzzing"). Returns true when read.
inline bool run_mesh_read(const std::string& ext, const std::uint8_t* data, std::size_t size) {
  static const auto path = scratch_file(".read" + ext);
  write_file(path, data, size);
  std::vector<std::string> notes;
  try {
    (void)geometry::read_mesh(path, Eigen::Matrix4d::Identity(), true, notes);
    return true;
  } catch (const geometry::GeometryError&) {
    return false;
  }
}

// A checkpoint file (`varsph run --restart FILE`): read whole, digest checked, or refused.
inline bool run_checkpoint(const std::uint8_t* data, std::size_t size) {
  static const auto path = scratch_file(".h5");
  write_file(path, data, size);
  try {
    (void)io::read_checkpoint(path);
    return true;
  } catch (const InputError&) {
    return false;
  }
}

}  // namespace varsph::fuzz
