#pragma once
// A dimension-free description of one output frame: points and named arrays pointing into the
// particle store, plus the field data every VTU carries (CONTRACT.md).
#include <cstdint>
#include <string>
#include <vector>

#include "core/particle_store.hpp"

namespace varsph::io {

struct FrameArray {
  std::string name;
  const FieldBase* field;  // the registered array (components = dimension for vectors)
  bool pad_to_3;           // vectors are written with 3 components also in 2D
};

struct FrameData {
  int dimension = 2;
  const FieldBase* positions = nullptr;
  std::vector<FrameArray> arrays;
  bool float64 = false;  // output.precision
  // particles written: the first `count` of the store (a distributed run's owned ones); npos = all
  std::size_t count = std::size_t(-1);
  // when set, only these particles (store indices, each < count) are written, in this order: a lean frame
  // without the static walls, or the static walls alone (output.static_boundary, issue 35)
  const std::vector<std::uint32_t>* select = nullptr;
  // field data `static_boundary`: the file, relative to this frame's folder, that holds the static boundary
  // particles this frame leaves out ("" = none: the frame holds every particle)
  std::string static_file;
  // field data
  double time = 0, dx = 0, h = 0, rho0 = 0, c0 = 0, support_radius = 0;
  std::int64_t step = 0;
  std::string kernel;
};

// Writes a VTU file (appended raw binary) atomically. IoError on failure.
void write_vtu(const std::string& path, const FrameData& frame);
// Writes the .pvtu that ties the pieces of a distributed frame together (the file VTK's parallel XML
// writer, vtkXMLPUnstructuredGridWriter, writes): the arrays' declarations, the frame's field data and
// one <Piece Source=.../> per piece, paths relative to the .pvtu. Atomically; IoError on failure.
void write_pvtu(const std::string& path, const FrameData& frame, const std::vector<std::string>& pieces);

}  // namespace varsph::io
