#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "core/errors.hpp"
#include "io/atomic_file.hpp"
#include "io/frame_data.hpp"

namespace varsph::io {
namespace {

double scalar_at(const FieldBase& f, std::size_t k) {
  switch (f.scalar_type()) {
    case ScalarType::Float64: return static_cast<const double*>(f.raw())[k];
    case ScalarType::Float32: return static_cast<const float*>(f.raw())[k];
    case ScalarType::Int64: return double(static_cast<const std::int64_t*>(f.raw())[k]);
    case ScalarType::Int32: return double(static_cast<const std::int32_t*>(f.raw())[k]);
  }
  return 0;
}

vtkSmartPointer<vtkDataArray> make_array(const FrameArray& fa, std::size_t n, bool float64) {
  const FieldBase& f = *fa.field;
  const int comps = fa.pad_to_3 ? 3 : f.components();
  vtkSmartPointer<vtkDataArray> arr;
  switch (f.scalar_type()) {
    case ScalarType::Int64: arr = vtkSmartPointer<vtkTypeInt64Array>::New(); break;
    case ScalarType::Int32: arr = vtkSmartPointer<vtkIntArray>::New(); break;
    default:
      if (float64) arr = vtkSmartPointer<vtkDoubleArray>::New();
      else arr = vtkSmartPointer<vtkFloatArray>::New();
  }
  arr->SetName(fa.name.c_str());
  arr->SetNumberOfComponents(comps);
  arr->SetNumberOfTuples(vtkIdType(n));
  const int fc = f.components();
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < comps; ++c)
      arr->SetComponent(vtkIdType(i), c, c < fc ? scalar_at(f, i * std::size_t(fc) + std::size_t(c)) : 0.0);
  return arr;
}

template <class A, class T>
void add_field(vtkFieldData* fd, const char* name, T value) {
  vtkNew<A> a;
  a->SetName(name);
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

}  // namespace

void write_vtu(const std::string& path, const FrameData& frame) {
  const FieldBase& pos = *frame.positions;
  const std::size_t n = pos.size();
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  points->SetDataType(frame.float64 ? VTK_DOUBLE : VTK_FLOAT);
  points->SetNumberOfPoints(vtkIdType(n));
  const int d = pos.components();
  for (std::size_t i = 0; i < n; ++i) {
    double p[3] = {0, 0, 0};
    for (int c = 0; c < d; ++c) p[c] = scalar_at(pos, i * std::size_t(d) + std::size_t(c));
    points->SetPoint(vtkIdType(i), p);
  }
  grid->SetPoints(points);
  // one vertex cell per particle so ParaView renders them without a Glyph filter
  vtkNew<vtkIdTypeArray> conn;
  conn->SetNumberOfValues(vtkIdType(n));
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfValues(vtkIdType(n) + 1);
  for (std::size_t i = 0; i < n; ++i) {
    conn->SetValue(vtkIdType(i), vtkIdType(i));
    offsets->SetValue(vtkIdType(i), vtkIdType(i));
  }
  offsets->SetValue(vtkIdType(n), vtkIdType(n));
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, conn);
  grid->SetCells(VTK_VERTEX, cells);

  for (const auto& fa : frame.arrays) grid->GetPointData()->AddArray(make_array(fa, n, frame.float64));

  vtkFieldData* fd = grid->GetFieldData();
  add_field<vtkDoubleArray>(fd, "time", frame.time);
  add_field<vtkTypeInt64Array>(fd, "step", frame.step);
  add_field<vtkDoubleArray>(fd, "dx", frame.dx);
  add_field<vtkDoubleArray>(fd, "h", frame.h);
  add_field<vtkDoubleArray>(fd, "rho0", frame.rho0);
  add_field<vtkDoubleArray>(fd, "c0", frame.c0);
  add_field<vtkDoubleArray>(fd, "support_radius", frame.support_radius);
  add_field<vtkIntArray>(fd, "dimension", frame.dimension);
  vtkNew<vtkStringArray> kernel;
  kernel->SetName("kernel");
  kernel->InsertNextValue(frame.kernel);
  fd->AddArray(kernel);

  write_atomically(path, [&](const std::filesystem::path& tmp) {
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetFileName(tmp.c_str());
    writer->SetInputData(grid);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorTypeToNone();
    // Write() can return 1 after a failed stream write (disk full): the error code tells
    if (writer->Write() != 1 || writer->GetErrorCode() != vtkErrorCode::NoError)
      throw IoError(path + ": VTK could not write the frame (VTK error code " +
                    std::to_string(writer->GetErrorCode()) + "; disk full or not writable?)");
  });
}

}  // namespace varsph::io
