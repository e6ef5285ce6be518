#pragma once
// Output of a distributed run, written so that a user opens the same things as after a serial run:
// one .pvd whose frames are .pvtu files (each rank writes its owned particles as a piece), and
// checkpoints in pieces with a manifest that any number of ranks (or the serial program) restarts
// from. In one process both write exactly what the serial program writes. Collective: an I/O error on
// any rank is an IoError on every rank (parallel/collective.hpp), so no rank is left waiting.
#include <cstddef>
#include <filesystem>
#include <string>

#include "core/particle_store.hpp"
#include "io/checkpoint.hpp"
#include "io/frame_data.hpp"
#include "io/run_directory.hpp"
#include "parallel/communicator.hpp"

namespace varsph::parallel {

// Frame `index` (its `count` particles are this rank's owned ones). Returns its path relative to the
// run directory, for the .pvd.
std::string write_frame(Communicator& comm, const io::RunDirectory& dir, long index, const io::FrameData& frame);

// The checkpoint at `path` of the store's first `owned` particles (a piece per rank and a manifest when
// distributed). `header` need only be complete on rank 0.
void write_checkpoint(Communicator& comm, const std::filesystem::path& path, const io::CheckpointHeader& header,
                      const ParticleStore& store, std::size_t owned);

}  // namespace varsph::parallel
