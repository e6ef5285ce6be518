#pragma once
// HDF5 checkpoints (docs/results.md has the layout). A checkpoint holds every registered particle field
// with flags().checkpointed, in storage order, plus the clock, dt, the integrator's and the runner's
// state, the resolved scene and the program and format versions. Written atomically (temp + rename).
// Reading validates the whole file before anything is used: a truncated, corrupted or foreign file is an
// InputError (exit 2) naming the file.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/particle_store.hpp"

namespace varsph::io {

// Bumped whenever the layout changes; a file with a newer version is refused. 2: the root attribute
// content_digest (format 1 files, without it, are still read).
constexpr int kCheckpointFormatVersion = 2;

struct CheckpointHeader {
  int format_version = kCheckpointFormatVersion;
  std::string program_version;
  std::string real_type;  // "double" | "float" (the build's Real)
  int dimension = 2;
  std::int64_t step = 0;
  double time = 0, dt = 0;
  std::int64_t particles = 0;
  nlohmann::json scene;             // Scene::resolved
  std::string integrator;           // integrator name
  nlohmann::json integrator_state;  // Integrator::save_state()
  nlohmann::json runner_state;      // frame numbering, next output/checkpoint times, fp statistics
};

struct CheckpointArray {
  std::string name;
  ScalarType type = ScalarType::Float64;
  int components = 1;
  std::vector<std::byte> bytes;  // particles * components scalars
};

struct Checkpoint {
  CheckpointHeader header;
  std::vector<CheckpointArray> arrays;  // in the order they were registered
  const CheckpointArray* find(const std::string& name) const;
};

// Writes `path` atomically from the store's checkpointed fields. IoError (exit 4) on failure; no
// partial file is left under `path` (only the temporary is written, and it is removed on failure).
void write_checkpoint(const std::filesystem::path& path, const CheckpointHeader& header, const ParticleStore& store);

// Reads and validates a checkpoint. InputError (exit 2) on anything wrong with the file.
Checkpoint read_checkpoint(const std::filesystem::path& path);

// "checkpoints/step_000012345.h5"
std::string checkpoint_file_name(std::int64_t step);
// The checkpoints in `dir` (step_*.h5), sorted by step.
std::vector<std::pair<std::int64_t, std::filesystem::path>> list_checkpoints(const std::filesystem::path& dir);

}  // namespace varsph::io
