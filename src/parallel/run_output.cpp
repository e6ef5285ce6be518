#include "parallel/run_output.hpp"

#include <vector>

#include "core/errors.hpp"
#include "parallel/collective.hpp"

namespace varsph::parallel {

std::string write_frame(Communicator& comm, const io::RunDirectory& dir, long index, const io::FrameData& frame) {
  if (!dir.pieces) {
    io::write_vtu(dir.frame(index).string(), frame);
    return dir.frame_relative(index);
  }
  const auto piece_dir = (dir.root / dir.piece_relative(index, 0)).parent_path();
  collectively(comm, [&] {
    if (!comm.root()) return;
    std::error_code ec;
    std::filesystem::create_directories(piece_dir, ec);
    if (ec) throw IoError(piece_dir.string() + ": cannot create the directory of the frame's pieces: " + ec.message());
  });
  collectively(comm, [&] { io::write_vtu((dir.root / dir.piece_relative(index, comm.rank())).string(), frame); });
  collectively(comm, [&] {
    if (!comm.root()) return;
    // piece paths relative to the .pvtu (frames/): NAME_000042/NAME_000042_R.vtu
    std::vector<std::string> pieces;
    const std::size_t skip = std::string("frames/").size();
    for (int r = 0; r < comm.size(); ++r) pieces.push_back(dir.piece_relative(index, r).substr(skip));
    io::write_pvtu(dir.frame(index).string(), frame, pieces);
  });
  return dir.frame_relative(index);
}

void write_checkpoint(Communicator& comm, const std::filesystem::path& path, const io::CheckpointHeader& header,
                      const ParticleStore& store, std::size_t owned) {
  if (comm.size() == 1) {
    io::write_checkpoint(path, header, store);
    return;
  }
  collectively(comm, [&] {
    if (!comm.root()) return;
    std::error_code ec;
    std::filesystem::create_directories(io::checkpoint_pieces_dir(path), ec);
    if (ec) throw IoError(io::checkpoint_pieces_dir(path).string() + ": cannot create the directory of the "
                          "checkpoint's pieces: " + ec.message());
  });
  collectively(comm, [&] { io::write_checkpoint_piece(path, comm.rank(), store, owned); });
  const std::vector<std::int64_t> counts = comm.allgather(std::int64_t(owned));
  // the manifest last: a checkpoint whose manifest exists is complete
  collectively(comm, [&] {
    if (comm.root()) io::write_checkpoint_manifest(path, header, store, counts);
  });
}

}  // namespace varsph::parallel
