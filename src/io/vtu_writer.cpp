// VTU frames written by hand, streaming: the XML header, then every array converted in fixed-size chunks
// straight from the particle store into the appended raw block. No VTK copy of the particle arrays is
// made (a frame used to cost ~110 bytes per particle of VTK arrays at the run's peak resident size).
// The format is what vtkXMLUnstructuredGridWriter writes with SetDataModeToAppended,
// EncodeAppendedDataOff and no compression (VTKFile version 1.0, UInt64 block headers, little endian);
// ParaView and vtkXMLUnstructuredGridReader read it. Field data are written inline (ascii, doubles with 17
// significant digits: exact).
#include <bit>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "io/atomic_file.hpp"
#include "io/frame_data.hpp"

namespace varsph::io {
namespace {

static_assert(std::endian::native == std::endian::little, "VTU writer assumes a little-endian host");

constexpr std::size_t kChunkBytes = std::size_t(1) << 20;  // conversion buffer: 1 MiB whatever the size

// One appended array: what it is called, its VTK type and how to produce its values.
struct OutArray {
  std::string name;
  const char* vtk_type;
  int out_components;
  std::size_t out_scalar_bytes;
  // source: a registered field (components fc, padded to out_components with zeros), or a generated one
  const FieldBase* field = nullptr;
  enum class Gen { None, Connectivity, Offsets, Types } gen = Gen::None;
  std::uint64_t bytes(std::size_t n) const { return std::uint64_t(n) * std::uint64_t(out_components) * out_scalar_bytes; }
};

const char* type_name(ScalarType t, bool float64) {
  switch (t) {
    case ScalarType::Int64: return "Int64";
    case ScalarType::Int32: return "Int32";
    default: return float64 ? "Float64" : "Float32";
  }
}
std::size_t type_bytes(ScalarType t, bool float64) {
  switch (t) {
    case ScalarType::Int64: return 8;
    case ScalarType::Int32: return 4;
    default: return float64 ? 8 : 4;
  }
}

// particles first .. first + count of the written sequence: store rows first + i, or sel[first + i]
template <class In, class Out>
void convert(const In* in, int fc, int oc, std::size_t first, std::size_t count, Out* out, const std::uint32_t* sel) {
  for (std::size_t i = 0; i < count; ++i) {
    const In* src = in + (sel ? std::size_t(sel[first + i]) : first + i) * std::size_t(fc);
    Out* dst = out + i * std::size_t(oc);
    for (int c = 0; c < oc; ++c) dst[c] = c < fc ? Out(src[c]) : Out(0);
  }
}

template <class Out>
void convert_field(const FieldBase& f, int oc, std::size_t first, std::size_t count, Out* out,
                   const std::uint32_t* sel) {
  const int fc = f.components();
  switch (f.scalar_type()) {
    case ScalarType::Float64: convert(static_cast<const double*>(f.raw()), fc, oc, first, count, out, sel); break;
    case ScalarType::Float32: convert(static_cast<const float*>(f.raw()), fc, oc, first, count, out, sel); break;
    case ScalarType::Int64: convert(static_cast<const std::int64_t*>(f.raw()), fc, oc, first, count, out, sel); break;
    case ScalarType::Int32: convert(static_cast<const std::int32_t*>(f.raw()), fc, oc, first, count, out, sel); break;
  }
}

class File {
 public:
  explicit File(const std::filesystem::path& p) : path_(p.string()), f_(std::fopen(path_.c_str(), "wb")) {
    if (!f_) throw IoError(path_ + ": cannot open for writing: " + std::strerror(errno));
  }
  ~File() {
    if (f_) std::fclose(f_);
  }
  void write(const void* data, std::size_t n) {
    if (n && std::fwrite(data, 1, n, f_) != n) fail();
  }
  void write(const std::string& s) { write(s.data(), s.size()); }
  void close() {
    const bool ok = std::fflush(f_) == 0;
    const int e = errno;
    const bool closed = std::fclose(f_) == 0;
    f_ = nullptr;
    if (!ok || !closed) {
      errno = ok ? errno : e;
      fail();
    }
  }

 private:
  [[noreturn]] void fail() {
    throw IoError(path_ + ": could not write the frame (disk full or not writable?): " + std::strerror(errno));
  }
  std::string path_;
  std::FILE* f_;
};

std::string num17(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string xml_escape(const std::string& s) {
  std::string o;
  for (char ch : s) {
    switch (ch) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += ch;
    }
  }
  return o;
}

// The field data every frame carries (CONTRACT.md), inline ascii (doubles with 17 digits: exact).
std::string field_data_xml(const FrameData& frame, const std::string& indent) {
  std::string xml;
  auto field_num = [&](const char* type, const char* name, const std::string& value) {
    xml += indent + "<DataArray type=\"" + std::string(type) + "\" Name=\"" + name +
           "\" NumberOfTuples=\"1\" format=\"ascii\">" + value + "</DataArray>\n";
  };
  field_num("Float64", "time", num17(frame.time));
  field_num("Int64", "step", std::to_string(frame.step));
  field_num("Float64", "dx", num17(frame.dx));
  field_num("Float64", "h", num17(frame.h));
  field_num("Float64", "rho0", num17(frame.rho0));
  field_num("Float64", "c0", num17(frame.c0));
  field_num("Float64", "support_radius", num17(frame.support_radius));
  field_num("Int32", "dimension", std::to_string(frame.dimension));
  {
    // a string array in ascii: the characters' codes, each string terminated by 0
    std::string codes;
    for (unsigned char ch : frame.kernel) codes += std::to_string(int(ch)) + " ";
    codes += "0";
    xml += indent + "<Array type=\"String\" Name=\"kernel\" NumberOfTuples=\"1\" format=\"ascii\">" + codes + "</Array>\n";
  }
  if (!frame.static_file.empty()) {  // where the static walls this frame leaves out are (issue 35)
    std::string codes;
    for (unsigned char ch : frame.static_file) codes += std::to_string(int(ch)) + " ";
    codes += "0";
    xml += indent + "<Array type=\"String\" Name=\"static_boundary\" NumberOfTuples=\"1\" format=\"ascii\">" +
           codes + "</Array>\n";
  }
  return xml;
}

}  // namespace

void write_vtu(const std::string& path, const FrameData& frame) {
  const FieldBase& pos = *frame.positions;
  const std::size_t n = frame.select ? frame.select->size() : std::min(pos.size(), frame.count);
  const std::uint32_t* sel = frame.select ? frame.select->data() : nullptr;
  const bool f64 = frame.float64;

  std::vector<OutArray> point_arrays;
  for (const auto& fa : frame.arrays) {
    const FieldBase& f = *fa.field;
    point_arrays.push_back({fa.name, type_name(f.scalar_type(), f64), fa.pad_to_3 ? 3 : f.components(),
                            type_bytes(f.scalar_type(), f64), &f});
  }
  OutArray points{"Points", f64 ? "Float64" : "Float32", 3, std::size_t(f64 ? 8 : 4), &pos};
  // one vertex cell per particle so ParaView renders them without a Glyph filter
  OutArray conn{"connectivity", "Int64", 1, 8, nullptr, OutArray::Gen::Connectivity};
  OutArray offs{"offsets", "Int64", 1, 8, nullptr, OutArray::Gen::Offsets};
  OutArray types{"types", "UInt8", 1, 1, nullptr, OutArray::Gen::Types};

  // XML header with the offsets of every array in the appended block (8-byte length header each)
  std::uint64_t offset = 0;
  auto decl = [&](const OutArray& a) {
    std::string s = "        <DataArray type=\"" + std::string(a.vtk_type) + "\" Name=\"" + xml_escape(a.name) + "\"";
    if (a.out_components > 1) s += " NumberOfComponents=\"" + std::to_string(a.out_components) + "\"";
    s += " format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>\n";
    offset += 8 + a.bytes(n);
    return s;
  };
  std::string xml;
  xml += "<?xml version=\"1.0\"?>\n";
  xml += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  xml += "  <UnstructuredGrid>\n    <FieldData>\n";
  xml += field_data_xml(frame, "      ");
  xml += "    </FieldData>\n";
  xml += "    <Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfCells=\"" + std::to_string(n) + "\">\n";
  xml += "      <PointData>\n";
  for (const auto& a : point_arrays) xml += decl(a);
  xml += "      </PointData>\n      <CellData>\n      </CellData>\n      <Points>\n";
  xml += decl(points);
  xml += "      </Points>\n      <Cells>\n";
  xml += decl(conn);
  xml += decl(offs);
  xml += decl(types);
  xml += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";

  write_atomically(path, [&](const std::filesystem::path& tmp) {
    File out(tmp);
    out.write(xml);
    std::unique_ptr<std::byte[]> buf(new std::byte[kChunkBytes]);
    auto stream = [&](const OutArray& a) {
      const std::uint64_t len = a.bytes(n);
      out.write(&len, sizeof len);
      const std::size_t tuple_bytes = std::size_t(a.out_components) * a.out_scalar_bytes;
      const std::size_t per_chunk = kChunkBytes / tuple_bytes;
      for (std::size_t first = 0; first < n; first += per_chunk) {
        const std::size_t cnt = std::min(per_chunk, n - first);
        if (a.field) {
          const int oc = a.out_components;
          if (std::strcmp(a.vtk_type, "Float64") == 0) convert_field(*a.field, oc, first, cnt, reinterpret_cast<double*>(buf.get()), sel);
          else if (std::strcmp(a.vtk_type, "Float32") == 0) convert_field(*a.field, oc, first, cnt, reinterpret_cast<float*>(buf.get()), sel);
          else if (std::strcmp(a.vtk_type, "Int64") == 0) convert_field(*a.field, oc, first, cnt, reinterpret_cast<std::int64_t*>(buf.get()), sel);
          else convert_field(*a.field, oc, first, cnt, reinterpret_cast<std::int32_t*>(buf.get()), sel);
        } else if (a.gen == OutArray::Gen::Types) {
          std::memset(buf.get(), 1, cnt);  // VTK_VERTEX
        } else {
          auto* v = reinterpret_cast<std::int64_t*>(buf.get());
          // VTU offsets are the end of each cell's connectivity: i + 1 for one-point cells
          const std::int64_t add = a.gen == OutArray::Gen::Offsets ? 1 : 0;
          for (std::size_t i = 0; i < cnt; ++i) v[i] = std::int64_t(first + i) + add;
        }
        out.write(buf.get(), cnt * tuple_bytes);
      }
    };
    for (const auto& a : point_arrays) stream(a);
    stream(points);
    stream(conn);
    stream(offs);
    stream(types);
    out.write(std::string("\n  </AppendedData>\n</VTKFile>\n"));
    out.close();
  });
}

void write_pvtu(const std::string& path, const FrameData& frame, const std::vector<std::string>& pieces) {
  const bool f64 = frame.float64;
  std::string xml;
  xml += "<?xml version=\"1.0\"?>\n";
  xml += "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  xml += "  <PUnstructuredGrid GhostLevel=\"0\">\n    <FieldData>\n";
  xml += field_data_xml(frame, "      ");
  xml += "    </FieldData>\n    <PPointData>\n";
  for (const auto& fa : frame.arrays) {
    const FieldBase& f = *fa.field;
    const int oc = fa.pad_to_3 ? 3 : f.components();
    xml += "      <PDataArray type=\"" + std::string(type_name(f.scalar_type(), f64)) + "\" Name=\"" +
           xml_escape(fa.name) + "\"" + (oc > 1 ? " NumberOfComponents=\"" + std::to_string(oc) + "\"" : "") + "/>\n";
  }
  xml += "    </PPointData>\n    <PPoints>\n";
  xml += std::string("      <PDataArray type=\"") + (f64 ? "Float64" : "Float32") +
         "\" Name=\"Points\" NumberOfComponents=\"3\"/>\n";
  xml += "    </PPoints>\n";
  // the pieces' vertex cells, declared as the pieces write them: without PCells VTK's parallel reader
  // builds the merged grid's cells wrongly (ParaView's Threshold then crashed in postprocess.py)
  xml += "    <PCells>\n      <PDataArray type=\"Int64\" Name=\"connectivity\"/>\n"
         "      <PDataArray type=\"Int64\" Name=\"offsets\"/>\n      <PDataArray type=\"UInt8\" Name=\"types\"/>\n"
         "    </PCells>\n";
  for (const auto& p : pieces) xml += "    <Piece Source=\"" + xml_escape(p) + "\"/>\n";
  xml += "  </PUnstructuredGrid>\n</VTKFile>\n";
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    File out(tmp);
    out.write(xml);
    out.close();
  });
}

}  // namespace varsph::io
