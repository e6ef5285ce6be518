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
// A checkpoint in pieces (one per rank of a distributed run): DIR/step_N.h5 is the manifest (the header
// and the particle count of each piece, with a digest over them), DIR/step_N/piece_R.h5 hold the
// particles of rank R (each with its own content_digest). Readers see one checkpoint whose rows are the
// pieces' particles in piece order, whatever number of ranks reads it. Older programs refuse it
// (version 3) instead of misreading it.
constexpr int kCheckpointPiecesFormatVersion = 3;

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
  std::int64_t first_row = 0, rows = 0;  // the arrays hold rows [first_row, first_row + rows)
  const CheckpointArray* find(const std::string& name) const;
};

// Writes `path` atomically from the store's checkpointed fields. IoError (exit 4) on failure; no
// partial file is left under `path` (only the temporary is written, and it is removed on failure).
void write_checkpoint(const std::filesystem::path& path, const CheckpointHeader& header, const ParticleStore& store);

// Reads and validates a checkpoint (a single file or a manifest with its pieces). With parts > 1, only
// the share of reader `part`: rows [N part / parts, N (part + 1) / parts) of the N particles.
// InputError (exit 2) on anything wrong with the files.
Checkpoint read_checkpoint(const std::filesystem::path& path, int part = 0, int parts = 1);

// Checkpoints in pieces (distributed runs; see kCheckpointPiecesFormatVersion). Every rank writes its
// piece, then one rank the manifest: the manifest existing means the checkpoint is complete.
std::filesystem::path checkpoint_pieces_dir(const std::filesystem::path& manifest);  // DIR/step_N
std::filesystem::path checkpoint_piece_path(const std::filesystem::path& manifest, int piece);
void write_checkpoint_piece(const std::filesystem::path& manifest, int piece, const ParticleStore& store,
                            std::size_t count);  // the store's first `count` particles
void write_checkpoint_manifest(const std::filesystem::path& path, const CheckpointHeader& header,
                               const ParticleStore& store, const std::vector<std::int64_t>& piece_counts);
// Removes a checkpoint file and its pieces, if any.
void remove_checkpoint(const std::filesystem::path& path);

// "checkpoints/step_000012345.h5"
std::string checkpoint_file_name(std::int64_t step);
// The checkpoints in `dir` (step_*.h5), sorted by step.
std::vector<std::pair<std::int64_t, std::filesystem::path>> list_checkpoints(const std::filesystem::path& dir);

}  // namespace varsph::io
