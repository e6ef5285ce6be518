#include "detail/input_checks.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "varsph/geometry/geometry_error.h"

namespace varsph::geometry::detail {
namespace {

std::string read_all(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Binary STL: 80-byte header, uint32 count, 50 bytes per triangle. A file that does not start with
// "solid" is binary, so its count must fit its size (CGAL would otherwise read whatever garbage follows).
void check_stl(const std::filesystem::path& path, std::uintmax_t size) {
  std::ifstream in(path, std::ios::binary);
  char head[84] = {};
  in.read(head, sizeof head);
  const bool ascii = std::strncmp(head, "solid", 5) == 0;
  if (ascii) return;  // ASCII STL (or a binary one whose header starts with "solid": then CGAL checks)
  if (size < 84)
    throw GeometryError(path, "is " + std::to_string(size) + " bytes, too short for a binary STL (84-byte header) "
                              "and does not start with 'solid' (ASCII STL); expected an STL file");
  std::uint32_t n = 0;
  std::memcpy(&n, head + 80, 4);  // little-endian, as STL specifies (x86)
  const std::uintmax_t need = 84 + 50 * std::uintmax_t(n);
  if (need > size)
    throw GeometryError(path, "binary STL header declares " + std::to_string(n) + " triangles (" +
                              std::to_string(need) + " bytes) but the file has " + std::to_string(size) +
                              " bytes; expected a complete binary STL (truncated or not an STL file?)");
  // the raw float vertices: CGAL's binary reader merges equal points in an ordered map, where a NaN
  // compares equal to anything and silently becomes another vertex (Hostile.AsciiStlWithNanVertex)
  char rec[50];
  for (std::uint32_t t = 0; t < n && in.read(rec, sizeof rec); ++t)
    for (int k = 0; k < 9; ++k) {
      float c;
      std::memcpy(&c, rec + 12 + 4 * k, 4);
      if (std::isfinite(c)) continue;
      std::ostringstream m;
      m << "vertex " << 3 * std::uintmax_t(t) + std::uintmax_t(k / 3) << " (triangle " << t << ") has coordinate "
        << "xyz"[k % 3] << " = " << c << " in the file; expected finite numbers (the exporter wrote NaN or infinity)";
      throw GeometryError(path, m.str());
    }
}

// OFF: "[ST][C][N][4][n]OFF [dim] nv nf ne" (ASCII). Each vertex line takes at least 6 bytes
// ("0 0 0\n"), each face at least 2, so the declared counts must fit the size.
void check_off(const std::filesystem::path& path, std::uintmax_t size) {
  std::ifstream in(path, std::ios::binary);
  std::string text(4096, '\0');
  in.read(text.data(), std::streamsize(text.size()));
  text.resize(std::size_t(in.gcount()));
  std::istringstream s(text);
  std::vector<std::string> tok;
  std::string line;
  while (tok.size() < 6 && std::getline(s, line)) {
    if (auto h = line.find('#'); h != std::string::npos) line.resize(h);
    std::istringstream ls(line);
    for (std::string t; ls >> t;) tok.push_back(t);
  }
  if (tok.empty() || tok[0].size() < 3 || tok[0].compare(tok[0].size() - 3, 3, "OFF") != 0) return;  // CGAL decides
  std::size_t k = 1;
  if (tok[0].find('n') != std::string::npos) ++k;  // nOFF: dimension first
  if (k < tok.size() && tok[k] == "BINARY") return;  // binary OFF: CGAL reads counts itself
  if (k + 1 >= tok.size()) return;
  const double nv = std::strtod(tok[k].c_str(), nullptr), nf = std::strtod(tok[k + 1].c_str(), nullptr);
  if (!(nv >= 0) || !(nf >= 0))
    throw GeometryError(path, "OFF header declares negative vertex or face counts ('" + tok[k] + " " + tok[k + 1] +
                              "'); expected 'OFF nv nf ne'");
  if (6 * nv + 2 * nf > double(size))
    throw GeometryError(path, "OFF header declares " + tok[k] + " vertices and " + tok[k + 1] +
                              " faces, more than a file of " + std::to_string(size) +
                              " bytes can hold; expected counts that match the file (truncated or damaged header?)");
}

// PLY: walks the header and the element data without storing it, so that no element count and no list
// length can exceed what the file holds (CGAL resizes to a list's declared length before reading it).
struct PlyProperty {
  bool list = false;
  int count_bytes = 0, value_bytes = 0;
};
struct PlyElement {
  std::string name;
  double count = 0;
  std::vector<PlyProperty> props;
};

int ply_type_bytes(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

void check_ply(const std::filesystem::path& path, std::uintmax_t size) {
  const std::string data = read_all(path);
  const auto end = data.find("end_header");
  if (data.compare(0, 3, "ply") != 0 || end == std::string::npos) return;  // CGAL reports it
  auto bad = [&](const std::string& what) {
    throw GeometryError(path, what + "; expected a PLY file whose header matches its data (truncated or damaged?)");
  };
  std::istringstream head(data.substr(0, end));
  std::string line, format;
  std::vector<PlyElement> elements;
  while (std::getline(head, line)) {
    std::istringstream ls(line);
    std::string w;
    ls >> w;
    if (w == "format") ls >> format;
    if (w == "element") {
      PlyElement e;
      std::string n;
      ls >> e.name >> n;
      e.count = std::strtod(n.c_str(), nullptr);
      if (!(e.count >= 0) || e.count > double(size))
        bad("PLY header declares " + n + " '" + e.name + "' elements, more than a file of " + std::to_string(size) +
            " bytes can hold");
      elements.push_back(e);
    }
    if (w == "property" && !elements.empty()) {
      std::string t;
      ls >> t;
      PlyProperty p;
      if (t == "list") {
        std::string ct, vt;
        ls >> ct >> vt;
        p.list = true;
        p.count_bytes = ply_type_bytes(ct);
        p.value_bytes = ply_type_bytes(vt);
      } else {
        p.value_bytes = ply_type_bytes(t);
      }
      if (p.value_bytes == 0 || (p.list && p.count_bytes == 0)) return;  // unknown type: CGAL reports it
      elements.back().props.push_back(p);
    }
  }
  std::size_t pos = data.find('\n', end);
  pos = pos == std::string::npos ? data.size() : pos + 1;
  const bool ascii = format == "ascii";
  if (!ascii && format != "binary_little_endian" && format != "binary_big_endian") return;  // CGAL reports it
  const bool big = format == "binary_big_endian";
  auto next_token = [&](double& v) {  // ASCII: next number, false at the end of the file
    while (pos < data.size() && std::isspace(static_cast<unsigned char>(data[pos]))) ++pos;
    if (pos >= data.size()) return false;
    const char* b = data.c_str() + pos;
    char* e = nullptr;
    v = std::strtod(b, &e);
    if (e == b) { v = NAN; ++pos; return true; }
    pos += std::size_t(e - b);
    return true;
  };
  auto read_count = [&](int bytes, double& v) {  // binary: an unsigned/signed integer count
    if (pos + std::size_t(bytes) > data.size()) return false;
    std::uint64_t u = 0;
    for (int b = 0; b < bytes; ++b) {
      const auto byte = static_cast<unsigned char>(data[pos + std::size_t(big ? b : bytes - 1 - b)]);
      u = (u << 8) | byte;
    }
    pos += std::size_t(bytes);
    // signed types: a set top bit is a negative length
    v = (bytes < 8 && (u >> (8 * bytes - 1)) != 0) ? -1.0 : double(u);
    return true;
  };
  for (const auto& e : elements) {
    for (double i = 0; i < e.count; ++i) {
      for (const auto& p : e.props) {
        double n = 1;
        if (p.list) {
          if (!(ascii ? next_token(n) : read_count(p.count_bytes, n)))
            bad("PLY data ends inside '" + e.name + "' element " + std::to_string(std::int64_t(i)));
          if (!(n >= 0) || n != std::floor(n) || n * (ascii ? 1 : p.value_bytes) > double(data.size() - pos))
            bad("PLY '" + e.name + "' element " + std::to_string(std::int64_t(i)) + " declares a list of " +
                std::to_string(n) + " entries, more than the rest of the file can hold");
        }
        if (ascii) {
          double v;
          for (double k = 0; k < n; ++k)
            if (!next_token(v)) bad("PLY data ends inside '" + e.name + "' element " + std::to_string(std::int64_t(i)));
        } else {
          const double bytes = n * p.value_bytes;
          if (bytes > double(data.size() - pos))
            bad("PLY data ends inside '" + e.name + "' element " + std::to_string(std::int64_t(i)));
          pos += std::size_t(bytes);
        }
      }
    }
  }
}

}  // namespace

void check_declared_counts(const std::filesystem::path& path, const std::string& ext) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) return;  // the reader reports unreadable files
  if (ext == ".stl") check_stl(path, size);
  else if (ext == ".off") check_off(path, size);
  else if (ext == ".ply") check_ply(path, size);
}

double binary_stl_area(const std::filesystem::path& path, const double A[9]) {
  std::ifstream in(path, std::ios::binary);
  char head[84] = {};
  in.read(head, sizeof head);
  if (in.gcount() < 84 || std::strncmp(head, "solid", 5) == 0) return -1;
  std::uint32_t n = 0;
  std::memcpy(&n, head + 80, 4);
  double area = 0;
  char rec[50];
  for (std::uint32_t t = 0; t < n && in.read(rec, sizeof rec); ++t) {
    double p[3][3];
    for (int v = 0; v < 3; ++v) {
      float x[3];
      std::memcpy(x, rec + 12 + 12 * v, 12);
      for (int a = 0; a < 3; ++a) p[v][a] = A[3 * a] * x[0] + A[3 * a + 1] * x[1] + A[3 * a + 2] * x[2];
    }
    double e1[3], e2[3];
    for (int a = 0; a < 3; ++a) { e1[a] = p[1][a] - p[0][a]; e2[a] = p[2][a] - p[0][a]; }
    const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                 cz = e1[0] * e2[1] - e1[1] * e2[0];
    area += 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz);
  }
  return area;
}

void check_coordinates(const std::filesystem::path& path, const double* xyz, std::size_t n, bool bounded,
                       const char* stage) {
  for (std::size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      const double c = xyz[3 * i + std::size_t(a)];
      if (std::isfinite(c) && (!bounded || std::abs(c) <= kMaxCoordinate)) continue;
      std::ostringstream m;
      m.precision(10);
      m << "vertex " << i << " has coordinate " << "xyz"[a] << " = " << c << " " << stage << "; expected "
        << (std::isfinite(c) ? "|coordinate| <= 1e9 m (is the file in other units, or the transform wrong?)"
                             : "finite numbers (the exporter wrote NaN or infinity)");
      throw GeometryError(path, m.str());
    }
}

}  // namespace varsph::geometry::detail
