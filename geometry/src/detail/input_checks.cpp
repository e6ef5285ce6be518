#include "detail/input_checks.h"

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <CGAL/IO/io.h>

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

// OFF, read as CGAL 5.5's File_scanner_OFF reads it: "[ST][C][N][4][n]OFF [dim] nv nf ne" (ASCII) or
// "... OFF BINARY" and big-endian int32 counts, then one line per vertex and one per face (ASCII). CGAL
// resizes the soup to the declared counts, and each face to the first number of its line, before it checks
// that the file holds them (a fuzzed face line "70150000000000001 0" asked for 5e17 bytes), so the counts
// and every face size are checked here first. A file CGAL cannot parse is left to CGAL's own error.
struct OffCursor {
  const std::string& d;
  std::size_t p = 0;
  bool space() const { return p < d.size() && std::isspace(static_cast<unsigned char>(d[p])); }
  void skip_space() { while (space()) ++p; }
  void skip_comments() {  // CGAL's skip_comment_OFF: whitespace and lines starting with '#'
    for (skip_space(); p < d.size() && d[p] == '#'; skip_space()) {
      const auto eol = d.find('\n', p);
      p = eol == std::string::npos ? d.size() : eol + 1;
    }
  }
  bool read_int(long long& v) {  // `in >> int`
    skip_space();
    if (p >= d.size()) return false;
    const char* b = d.c_str() + p;
    char* e = nullptr;
    errno = 0;
    v = std::strtoll(b, &e, 10);
    if (e == b || errno == ERANGE || v > INT32_MAX || v < INT32_MIN) return false;
    p += std::size_t(e - b);
    return true;
  }
  std::string line() {  // std::getline
    const auto eol = d.find('\n', p);
    std::string l = d.substr(p, eol == std::string::npos ? std::string::npos : eol - p);
    p = eol == std::string::npos ? d.size() : eol + 1;
    return l;
  }
};

void check_off(const std::filesystem::path& path, std::uintmax_t size) {
  const std::string data = read_all(path);
  OffCursor c{data};
  auto bad = [&](const std::string& what) {
    throw GeometryError(path, what + "; expected an OFF file whose counts match its data (truncated or damaged?)");
  };
  c.skip_comments();
  if (c.p >= data.size()) return;
  std::string key(1, data[c.p++]);
  while (c.p < data.size() && std::isalnum(static_cast<unsigned char>(data[c.p]))) key += data[c.p++];
  if (c.p < data.size()) ++c.p;  // CGAL consumes the character that ends the keyword
  if (key.size() < 3 || key.compare(key.size() - 3, 3, "OFF") != 0) return;  // SKEL or not OFF: CGAL decides
  const std::string flags = key.substr(0, key.size() - 3);
  const bool ndim = flags.find('n') != std::string::npos;
  // colours, normals and textures are not used, and CGAL's reading of them is unsafe on damaged input: it
  // casts a colour of 1020 to an unsigned char (undefined behaviour) and read a fuzzed STOFF's texture
  // past the end of its line (SIGSEGV); so such files are refused rather than walked, as binary ones are
  if (flags.find_first_of("STCN") != std::string::npos)
    bad("OFF with colours, normals or textures ('" + key + "') is not read; expected OFF, 4OFF or nOFF (export "
        "without them)");
  c.skip_comments();
  long long nv = 0, nf = 0, ne = 0;
  // the edge count is not used, but CGAL doubles it in an int (a fuzzed binary OFF declared 1627389951:
  // signed overflow); a file cannot list more edges than it has bytes
  auto check_edge_count = [&](long long n) {
    if (n < 0 || double(n) > std::min(double(size), 1073741823.0))
      bad("OFF header declares " + std::to_string(n) + " edges; expected 0 to " +
          std::to_string(std::min<std::uintmax_t>(size, 1073741823u)) + " (at most the file's size in bytes)");
  };
  if (c.p < data.size() && !std::isdigit(static_cast<unsigned char>(data[c.p])) && data[c.p] != '-') {
    // "OFF BINARY": big-endian int32 [dim] nv nf ne after the end of that line
    if (data.compare(c.p, 6, "BINARY") != 0) return;
    if (!flags.empty())
      bad("binary OFF with '" + flags + "' (colours, normals, textures or dimensions) is not read");
    const auto eol = data.find('\n', c.p);
    std::size_t q = eol == std::string::npos ? data.size() : eol + 1;
    auto i32 = [&](long long& v) {
      if (q + 4 > data.size()) return false;
      std::uint32_t u = 0;
      for (int k = 0; k < 4; ++k) u = (u << 8) | static_cast<unsigned char>(data[q + std::size_t(k)]);
      q += 4;
      v = static_cast<std::int32_t>(u);
      return true;
    };
    if (!i32(nv) || !i32(nf) || !i32(ne)) return;
    check_edge_count(ne);
    if (nv < 0 || nf < 0 || 12.0 * double(nv) + 4.0 * double(nf) > double(size - q))
      bad("binary OFF header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
          " faces, more than a file of " + std::to_string(size) + " bytes can hold");
    q += 12 * std::size_t(nv);  // three float32 per vertex
    for (long long f = 0; f < nf; ++f) {
      long long n = 0;
      if (!i32(n)) return;  // CGAL reports the premature end
      if (n < 0 || 4.0 * double(n) > double(data.size() - q))
        bad("binary OFF face " + std::to_string(f) + " declares " + std::to_string(n) +
            " vertices, more than the rest of the file holds");
      q += 4 * std::size_t(n);
    }
    return;
  }
  if (ndim && !c.read_int(nv)) return;  // nOFF: the dimension first
  if (!c.read_int(nv) || !c.read_int(nf) || !c.read_int(ne)) return;
  check_edge_count(ne);
  if (nv < 0 || nf < 0)
    bad("OFF header declares negative vertex or face counts (" + std::to_string(nv) + " " + std::to_string(nf) + ")");
  // each vertex line takes at least 6 bytes ("0 0 0\n"), each face at least 2
  if (6.0 * double(nv) + 2.0 * double(nf) > double(size))
    bad("OFF header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
        " faces, more than a file of " + std::to_string(size) + " bytes can hold");
  for (long long v = 0; v < nv; ++v) {
    c.skip_comments();
    if (c.p >= data.size()) return;  // CGAL reports the premature end
    (void)c.line();
  }
  std::istringstream iss;  // one stream and one buffer for every face line: a mesh has millions
  std::vector<double> entries;
  for (long long f = 0; f < nf; ++f) {
    c.skip_comments();
    if (c.p >= data.size()) return;
    std::string l = c.line();
    if (const auto h = l.find('#'); h != std::string::npos) l.resize(h);
    // the line's numbers read exactly as CGAL reads them (IO::iformat of a double: with GCC the stream's
    // own >>, under which "5-20000" is 5 then -20000)
    iss.clear();
    iss.str(l);
    entries.clear();
    for (double d; iss >> CGAL::IO::iformat(d);) entries.push_back(d);
    if (entries.empty()) return;  // CGAL fails on this face
    const double n = entries[0];
    // a face of n corners takes at least 2n + 1 characters ("3 0 1 2")
    if (!(n >= 0 && n <= double(l.size()) / 2)) {
      std::string num;  // as written in the file
      std::istringstream(l) >> num;
      bad("OFF face " + std::to_string(f) + " declares " + num + " vertices but its line has " +
          std::to_string(l.size()) + " characters");
    }
    // CGAL casts each index to an unsigned integer: a negative one (a fuzzed "-7") is undefined behaviour
    for (std::size_t c = 1; double(c) <= n && c < entries.size(); ++c)
      if (!(entries[c] >= 0 && entries[c] < 9.2e18)) {
        std::ostringstream v;
        v << entries[c];
        bad("OFF face " + std::to_string(f) + " has vertex index " + v.str() + "; expected 0 to " +
            std::to_string(nv - 1));
      }
  }
}

// PLY: walks the header and the element data without storing it, so that no element count and no list
// length can exceed what the file holds (CGAL resizes to a list's declared length before reading it).
struct PlyProperty {
  bool list = false;
  int count_bytes = 0, value_bytes = 0;
  bool value_float = false;  // float/double values (CGAL reads them differently from integers in ASCII)
  double count_max = 0;      // the largest count its type holds
  std::string type, name;
};

bool ply_float_type(const std::string& t) { return t == "float" || t == "float32" || t == "double" || t == "float64"; }

double ply_int_max(const std::string& t) {
  if (t == "char" || t == "int8") return 127;
  if (t == "uchar" || t == "uint8") return 255;
  if (t == "short" || t == "int16") return 32767;
  if (t == "ushort" || t == "uint16") return 65535;
  if (t == "int" || t == "int32") return 2147483647.0;
  return 4294967295.0;
}
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
  {  // CGAL takes the first word of the first line, after any white space, as the signature
    std::istringstream first(data.substr(0, data.find('\n')));
    std::string signature;
    if (!(first >> signature) || signature != "ply") return;  // CGAL reports it
  }
  auto bad = [&](const std::string& what) {
    throw GeometryError(path, what + "; expected a PLY file whose header matches its data (truncated or damaged?)");
  };
  // the header line by line as CGAL 5.5's PLY_reader::init reads it (format on line 2, a keyword first
  // on each line, up to the line "end_header"), so that this walk and CGAL's read agree on every byte
  std::string line, format;
  std::vector<PlyElement> elements;
  std::size_t pos = 0, number = 0;
  bool ended = false;
  while (!ended && pos < data.size()) {
    const auto eol = data.find('\n', pos);
    line = data.substr(pos, eol == std::string::npos ? std::string::npos : eol - pos);
    pos = eol == std::string::npos ? data.size() : eol + 1;
    std::istringstream ls(line);
    std::string w;
    ls >> w;
    if (++number == 2) {
      ls >> format;
      continue;
    }
    if (number == 1) continue;
    if (w == "end_header") ended = true;
    if (w == "element") {
      PlyElement e;
      std::size_t n = 0;
      if (!(ls >> e.name >> n)) return;  // CGAL refuses the header
      e.count = double(n);
      if (e.count > double(size))
        bad("PLY header declares " + std::to_string(n) + " '" + e.name + "' elements, more than a file of " +
            std::to_string(size) + " bytes can hold");
      elements.push_back(e);
    }
    if (w == "property") {
      // CGAL appends a property to the last element (undefined behaviour without one: a fuzzed header)
      // and silently drops one of a type it does not know, which would shift its read against this walk
      if (elements.empty()) bad("PLY header has a property line before any element line");
      std::string t;
      ls >> t;
      PlyProperty p;
      if (t == "list") {
        std::string ct, vt;
        ls >> ct >> vt;
        p.list = true;
        p.count_bytes = ply_type_bytes(ct);
        p.value_bytes = ply_type_bytes(vt);
        p.value_float = ply_float_type(vt);
        if (p.count_bytes == 0 || ply_float_type(ct)) bad("PLY list count type '" + ct + "' is not an integer type");
        p.count_max = ply_int_max(ct);
      } else {
        p.value_bytes = ply_type_bytes(t);
        p.value_float = ply_float_type(t);
      }
      if (p.value_bytes == 0) bad("PLY property type '" + (p.list ? line : t) + "' is not a PLY type");
      p.type = t;
      ls >> p.name;
      // CGAL reads a vertex coordinate as a double or a float and nothing else (a fuzzed 'property uint32
      // x' made its reader call through a null pointer)
      if (elements.back().name == "vertex" && (p.name == "x" || p.name == "y" || p.name == "z") &&
          (p.list || !p.value_float))
        bad("PLY vertex property '" + p.name + "' has type '" + (p.list ? line : t) +
            "'; expected float, float32, double or float64");
      elements.back().props.push_back(p);
    }
  }
  // without it CGAL goes on to read elements from the end of the stream, into a list length it never set
  // (a fuzzed header: 0.02 s or 26 s and 1.4 GB from run to run)
  if (!ended) bad("PLY header has no end_header line");
  const bool ascii = format == "ascii";
  if (!ascii && format != "binary_little_endian" && format != "binary_big_endian") return;  // CGAL reports it
  const bool big = format == "binary_big_endian";
  // ASCII: the next value as CGAL reads it, the stream's own >> (IO::iformat is that with GCC; integers of
  // one or two bytes through a short). 0: the file ends, 1: read, 2: not a number (CGAL's read fails and it goes on with
  // the variable unset: a list length it never set asked for 4 GB in a fuzzed file). Integers are read wider than CGAL reads them: where CGAL fails on
  // an overflow the walk goes on, so it can only refuse more.
  const std::size_t body = std::min(pos, data.size());
  std::istringstream values(ascii ? data.substr(body) : std::string());
  auto remaining = [&]() -> double {  // bytes after the walk's position
    if (!ascii) return double(data.size() - pos);
    const auto at = values.tellg();
    return at < 0 ? 0.0 : double(data.size() - body) - double(at);
  };
  auto next_value = [&](bool floating, double& v) {
    values >> std::ws;
    if (values.eof()) return 0;
    if (floating) {
      if (!(values >> v)) return 2;
    } else {
      long long i = 0;
      if (!(values >> i)) return 2;
      v = double(i);
    }
    return 1;
  };
  auto read_count = [&](int bytes, double max, double& v) {  // binary: an unsigned/signed integer count
    if (pos + std::size_t(bytes) > data.size()) return false;
    std::uint64_t u = 0;
    for (int b = 0; b < bytes; ++b) {
      const auto byte = static_cast<unsigned char>(data[pos + std::size_t(big ? b : bytes - 1 - b)]);
      u = (u << 8) | byte;
    }
    pos += std::size_t(bytes);
    // signed types (max 2^(8 bytes - 1) - 1): a set top bit is a negative length
    const bool is_signed = max < std::ldexp(1.0, 8 * bytes - 1);
    v = (is_signed && (u >> (8 * bytes - 1)) != 0) ? -1.0 : double(u);
    return true;
  };
  for (const auto& e : elements) {
    for (double i = 0; i < e.count; ++i) {
      for (const auto& p : e.props) {
        double n = 1;
        if (p.list) {
          const int got = ascii ? next_value(false, n) : read_count(p.count_bytes, p.count_max, n) ? 1 : 0;
          if (got == 0) bad("PLY data ends inside '" + e.name + "' element " + std::to_string(std::int64_t(i)));
          if (got == 2)  // CGAL does not stop: it goes on with the value unset (a list length: gigabytes)
            bad("PLY '" + e.name + "' element " + std::to_string(std::int64_t(i)) + " holds a value that is not a number");
          if (!(n >= 0) || n > p.count_max || n * (ascii ? 1 : p.value_bytes) > remaining())
            bad("PLY '" + e.name + "' element " + std::to_string(std::int64_t(i)) + " declares a list of " +
                std::to_string(n) + " entries, more than the rest of the file can hold");
        }
        if (ascii) {
          double v;
          for (double k = 0; k < n; ++k) {
            const int got = next_value(p.value_float, v);
            if (got == 0) bad("PLY data ends inside '" + e.name + "' element " + std::to_string(std::int64_t(i)));
            if (got == 2)  // CGAL does not stop: it goes on with the value unset (a list length: gigabytes)
            bad("PLY '" + e.name + "' element " + std::to_string(std::int64_t(i)) + " holds a value that is not a number");
          }
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
