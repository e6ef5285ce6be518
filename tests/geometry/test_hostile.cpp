// Hostile and broken mesh files (issue 16): each is refused with a GeometryError naming the file, before
// anything allocates from what the file declares or samples from what it holds. The first four are the
// findings that hung (NaN vertex, random bytes as .stl, 200k random triangles) or corrupted the heap
// (coordinates of 1e300) before these checks existed.
#include <cstdint>
#include <random>

#include "test_helpers.h"
#include "varsph/geometry/geometry_error.h"
#include "varsph/geometry/sample_body.h"

using namespace varsph::geometry;

namespace {

BodyRequest surface(const std::filesystem::path& p, double dx = 0.05) {
  BodyRequest r;
  r.mesh = p;
  r.spacing = dx;
  r.max_particles = 1e7;  // the solver's default particles.max_count
  return r;
}

std::string error_of(const BodyRequest& r) {
  try {
    sample_body(r);
  } catch (const GeometryError& e) {
    EXPECT_EQ(e.file(), r.mesh);
    return e.what();
  }
  return "";
}

void tetrahedron(double scale, vt::MatrixXd& V, vt::MatrixXi& F) {
  V.resize(4, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  V *= scale;
  F.resize(4, 3);
  F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
}

}  // namespace

TEST(Hostile, AsciiStlWithNanVertex) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  tetrahedron(1.0, V, F);
  V(1, 0) = std::nan("");
  vt::write_stl_ascii(dir / "nan.stl", V, F);
  // CGAL's ASCII reader stops at "nan": the partial soup it returns is no longer used (it was, and hung)
  const std::string m = error_of(surface(dir / "nan.stl"));
  EXPECT_NE(m.find("nan.stl: cannot parse mesh file as stl"), std::string::npos) << m;
  // a binary STL stores the NaN as float bits, read as they are: the coordinate check names the vertex
  vt::write_stl_binary(dir / "nan_binary.stl", V, F);
  const std::string b = error_of(surface(dir / "nan_binary.stl"));
  EXPECT_NE(b.find("nan_binary.stl: vertex"), std::string::npos) << b;
  EXPECT_NE(b.find("= nan in the file; expected finite numbers"), std::string::npos) << b;
}

TEST(Hostile, RandomBytesNamedStl) {
  const auto dir = vt::temp_dir();
  std::mt19937 rng(16);
  std::string bytes(5000, '\0');
  for (auto& c : bytes) c = char(rng() & 0xff);
  bytes[0] = 'x';  // not "solid": read as binary
  std::ofstream(dir / "random.stl", std::ios::binary) << bytes;
  const std::string m = error_of(surface(dir / "random.stl"));
  EXPECT_NE(m.find("binary STL header declares"), std::string::npos) << m;
  EXPECT_NE(m.find("but the file has 5000 bytes"), std::string::npos) << m;
}

TEST(Hostile, ObjWithCoordinatesOf1e300) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  tetrahedron(1e300, V, F);
  {
    std::ofstream o(dir / "huge.obj");
    o.precision(17);
    for (int i = 0; i < 4; ++i) o << "v " << V(i, 0) << " " << V(i, 1) << " " << V(i, 2) << "\n";
    for (int f = 0; f < 4; ++f) o << "f " << F(f, 0) + 1 << " " << F(f, 1) + 1 << " " << F(f, 2) + 1 << "\n";
  }
  const std::string m = error_of(surface(dir / "huge.obj"));
  EXPECT_NE(m.find("= 1e+300 after the transform; expected |coordinate| <= 1e9 m"), std::string::npos) << m;
  // a transform that overflows a sane file is caught the same way
  tetrahedron(1.0, V, F);
  vt::write_off(dir / "tet.off", V, F);
  BodyRequest r = surface(dir / "tet.off");
  r.transform.topLeftCorner<3, 3>() *= 1e308;
  r.transform(0, 0) = 1e308 * 10;  // inf
  EXPECT_NE(error_of(r).find("invalid body request: transform must hold finite numbers"), std::string::npos);
  r.transform = Eigen::Matrix4d::Identity() * 1e12;
  r.transform(3, 3) = 1;
  EXPECT_NE(error_of(r).find("after the transform; expected |coordinate| <= 1e9 m"), std::string::npos);
}

TEST(Hostile, RandomTriangleSoupIsRefusedByItsParticleEstimate) {
  const auto dir = vt::temp_dir();
  const int n = 200000;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  vt::MatrixXd V(3 * n, 3);
  vt::MatrixXi F(n, 3);
  for (int i = 0; i < 3 * n; ++i) V.row(i) << u(rng), u(rng), u(rng);
  for (int f = 0; f < n; ++f) F.row(f) << 3 * f, 3 * f + 1, 3 * f + 2;
  vt::write_stl_binary(dir / "soup.stl", V, F);
  const std::string m = error_of(surface(dir / "soup.stl"));
  // sum of the areas of 200k random triangles in a unit cube ~ 3.0e4 m^2: / 0.05^2 = 1.2e7 particles
  EXPECT_NE(m.find("would produce about 1.2"), std::string::npos) << m;
  EXPECT_NE(m.find("e+07 particles (surface area 30"), std::string::npos) << m;
  EXPECT_NE(m.find("more than the limit of 1e+07"), std::string::npos) << m;
}

TEST(Hostile, DeclaredCountsBeyondTheFileSize) {
  const auto dir = vt::temp_dir();
  std::ofstream(dir / "big.off") << "OFF\n2000000000 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_NE(error_of(surface(dir / "big.off")).find("OFF header declares 2000000000 vertices"), std::string::npos);
  std::ofstream(dir / "neg.off") << "OFF\n-3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_NE(error_of(surface(dir / "neg.off")).find("negative vertex or face counts"), std::string::npos);
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  std::ofstream(dir / "list.ply") << head << "2000000000 0 1 2\n";
  EXPECT_NE(error_of(surface(dir / "list.ply")).find("declares a list of 2000000000"), std::string::npos);
  std::ofstream(dir / "short.ply") << head;  // the face is missing
  EXPECT_NE(error_of(surface(dir / "short.ply")).find("PLY data ends inside 'face' element 0"), std::string::npos);
  // CGAL doubles the (unused) edge count in an int: a fuzzed binary OFF overflowed it
  std::ofstream(dir / "edges.off") << "OFF\n3 1 1627389951\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_NE(error_of(surface(dir / "edges.off")).find("OFF header declares 1627389951 edges; expected 0 to"),
            std::string::npos);
  // CGAL casts a face's vertex indices to unsigned integers (a fuzzed -7: undefined behaviour)
  std::ofstream(dir / "negative.off") << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -7 2\n";
  EXPECT_NE(error_of(surface(dir / "negative.off")).find("OFF face 0 has vertex index -7; expected 0 to 2"),
            std::string::npos) << error_of(surface(dir / "negative.off"));
  // as CGAL reads it with GCC (the stream's >>), "1-7" is 1 then -7
  std::ofstream(dir / "glued.off") << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1-7\n";
  EXPECT_NE(error_of(surface(dir / "glued.off")).find("OFF face 0 has vertex index -7"), std::string::npos)
      << error_of(surface(dir / "glued.off"));
  // CGAL finds the signature after white space; so does the walk (a fuzzed header had a property before
  // any element behind a tab-indented "ply": CGAL took back() of no elements)
  std::ofstream(dir / "indented.ply") << "\t ply\nformat ascii 1.0\nproperty float x\nelement vertex 1\nend_header\n0\n";
  EXPECT_NE(error_of(surface(dir / "indented.ply")).find("PLY header has a property line before any element line"),
            std::string::npos) << error_of(surface(dir / "indented.ply"));
  // COFF: CGAL casts colours to unsigned char (a fuzzed 1020: undefined behaviour); colours are not used
  std::ofstream(dir / "colour.off") << "COFF\n3 1 0\n0 0 0 1020 0 0\n1 0 0 0 0 0\n0 1 0 0 0 0\n3 0 1 2\n";
  EXPECT_NE(error_of(surface(dir / "colour.off")).find("OFF with colours, normals or textures ('COFF') is not read"),
            std::string::npos);
  // STOFF: CGAL read a fuzzed texture past the end of its line (SIGSEGV)
  std::ofstream(dir / "texture.off") << "STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n";
  EXPECT_NE(error_of(surface(dir / "texture.off")).find("('STOFF') is not read"), std::string::npos);
  // a PLY header without end_header: CGAL went on into a list length it never set
  std::ofstream(dir / "open.ply") << "ply\nformat binary_little_endian 1.0\nelement vertex 1\n"
                                     "property list int int v\n";
  EXPECT_NE(error_of(surface(dir / "open.ply")).find("PLY header has no end_header line"), std::string::npos);
  // a value that is not a number: CGAL goes on with it unset (a fuzzed list length asked for 4 GB)
  std::ofstream(dir / "nan_count.ply") << head << "x 0 1 2\n";
  EXPECT_NE(error_of(surface(dir / "nan_count.ply")).find("PLY 'face' element 0 holds a value that is not a number"),
            std::string::npos) << error_of(surface(dir / "nan_count.ply"));
  // CGAL reads vertex coordinates as float or double only (a fuzzed uint32 x: a call through null)
  std::ofstream(dir / "intx.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty uint32 x\nproperty float y\n"
                                     "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                     "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_NE(error_of(surface(dir / "intx.ply")).find("PLY vertex property 'x' has type 'uint32'; expected float"),
            std::string::npos) << error_of(surface(dir / "intx.ply"));
  std::ofstream(dir / "count.ply") << "ply\nformat ascii 1.0\nelement vertex 9999999999\nproperty float x\nend_header\n";
  EXPECT_NE(error_of(surface(dir / "count.ply")).find("declares 9999999999 'vertex' elements"), std::string::npos);
  // a truncated binary STL: the header's count no longer fits
  vt::MatrixXd V; vt::MatrixXi F;
  tetrahedron(1.0, V, F);
  vt::write_stl_binary(dir / "cut.stl", V, F);
  std::filesystem::resize_file(dir / "cut.stl", 84 + 50 * 3 + 20);
  EXPECT_NE(error_of(surface(dir / "cut.stl")).find("declares 4 triangles (284 bytes) but the file has 254"),
            std::string::npos);
}

TEST(Hostile, PartialParseIsNotUsed) {
  const auto dir = vt::temp_dir();
  // an ASCII STL cut in the middle of its second facet: CGAL stops early; the first facet is not used
  std::ofstream(dir / "cut.stl") << "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
                                    "   vertex 0 1 0\n  endloop\n endfacet\n facet normal 0 0 1\n  outer loop\n"
                                    "   vertex 0 0 0\n";
  EXPECT_NE(error_of(surface(dir / "cut.stl")).find("cannot parse mesh file as stl"), std::string::npos);
}

TEST(Hostile, PolylineWithNonFiniteOrHugeCoordinates) {
  const auto dir = vt::temp_dir();
  std::ofstream(dir / "inf.poly2d") << "0 0\n1 0\n1 1e400\n";
  BodyRequest r = surface(dir / "inf.poly2d");
  r.dimension = 2;
  EXPECT_NE(error_of(r).find("inf.poly2d: line 3"), std::string::npos);
  std::ofstream(dir / "far.poly2d") << "0 0\n1 0\n1 2e9\n";
  r.mesh = dir / "far.poly2d";
  EXPECT_NE(error_of(r).find("line 3: point (1.000000, 2000000000.000000) is (1.000000, 2000000000.000000) m after "
                             "the transform"), std::string::npos) << error_of(r);
}

TEST(Hostile, MeshSpanningMoreThan1e7SpacingsIsRefused) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  tetrahedron(1e6, V, F);  // a 1000 km tetrahedron at dx = 0.05 m
  vt::write_off(dir / "far.off", V, F);
  BodyRequest r = surface(dir / "far.off");
  r.max_particles = 0;  // no budget: the span alone refuses it
  EXPECT_NE(error_of(r).find("more than 1e7 spacings"), std::string::npos) << error_of(r);
}

TEST(Hostile, EstimateCountsLayersAndVolume) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  vt::write_off(dir / "cube.off", V, F);
  BodyRequest r = surface(dir / "cube.off", 0.1);
  r.layers = 3;
  r.max_particles = 1799;  // 6 m^2 / 0.01 x 3 = 1800
  EXPECT_NE(error_of(r).find("would produce about 1.8e+03 particles (surface area 6.000000 m^2 / dx^2 x 3 layers"),
            std::string::npos) << error_of(r);
  r.max_particles = 1800;
  EXPECT_EQ(error_of(r), "");
  r.fill = "volume";
  r.layers = 1;
  r.max_particles = 999;  // 1 m^3 / 0.001
  EXPECT_NE(error_of(r).find("about 1e+03 particles (enclosed volume 1.000000 m^3"), std::string::npos);
  r.clip_min = Eigen::Vector3d(0, 0, 0);
  r.clip_max = Eigen::Vector3d(1, 1, 0.5);  // only half the cube is filled
  EXPECT_EQ(error_of(r), "");
}

namespace {

// A prism over a polygon with n corners (z = 0 and 1): two n-corner caps, n quads. `cap` lists the
// bottom cap's corners in the order the face gives them (the top cap is the simple outline reversed).
void write_prism_obj(const std::filesystem::path& p, const std::vector<std::array<double, 2>>& xy,
                     const std::vector<int>& cap) {
  std::ofstream o(p);
  o.precision(17);
  const int n = int(xy.size());
  for (int z = 0; z < 2; ++z)
    for (const auto& c : xy) o << "v " << c[0] << " " << c[1] << " " << z << "\n";
  o << "f";
  for (int i : cap) o << " " << i + 1;
  o << "\nf";
  for (int i = n - 1; i >= 0; --i) o << " " << n + i + 1;
  o << "\n";
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    o << "f " << i + 1 << " " << n + i + 1 << " " << n + j + 1 << " " << j + 1 << "\n";
  }
}

}  // namespace

// A fuzzed OBJ hexagon whose edges cross (fuzz/regressions/obj/refused_fuzz_outline_crosses_itself_hang.obj)
// kept CGAL's triangulate_faces busy for more than 290 s; such a face, and one that touches itself or
// turns back on itself, is refused before it (geometry/src/detail/polygon_outline.h), while simple
// polygons, convex or not, are still split.
TEST(Hostile, PolygonFaceWhoseEdgesCrossIsRefused) {
  const auto dir = vt::temp_dir();
  std::vector<std::array<double, 2>> hexagon;
  for (int i = 0; i < 6; ++i) hexagon.push_back({std::cos(i * M_PI / 3), std::sin(i * M_PI / 3)});
  write_prism_obj(dir / "hexagon.obj", hexagon, {5, 4, 3, 2, 1, 0});
  EXPECT_EQ(error_of(surface(dir / "hexagon.obj", 0.1)), "");
  // an arrow: not convex, still simple
  const std::vector<std::array<double, 2>> arrow{{0, 0}, {2, 0}, {2, -0.5}, {3, 0.5}, {2, 1.5}, {2, 1}, {0, 1}};
  write_prism_obj(dir / "arrow.obj", arrow, {6, 5, 4, 3, 2, 1, 0});
  EXPECT_EQ(error_of(surface(dir / "arrow.obj", 0.1)), "");
  // the hexagon's bottom cap with two corners swapped: edges 5-3 and 4-2 cross
  write_prism_obj(dir / "crossed.obj", hexagon, {5, 3, 4, 2, 1, 0});
  const std::string m = error_of(surface(dir / "crossed.obj", 0.1));
  EXPECT_NE(m.find("crossed.obj: a polygon face of 6 corners (the first at "), std::string::npos) << m;
  EXPECT_NE(m.find("is not a simple polygon seen along its normal"), std::string::npos) << m;
  // touching: two triangles' worth of outline whose corner (1, 0) lies on the edge (0, 0)-(2, 0)
  const std::vector<std::array<double, 2>> touching{{0, 0}, {2, 0}, {2, 2}, {1, 0}, {0, 2}};
  write_prism_obj(dir / "touching.obj", touching, {4, 3, 2, 1, 0});
  EXPECT_NE(error_of(surface(dir / "touching.obj", 0.1)).find("is not a simple polygon"), std::string::npos);
  // turning back: the fuzzed pentagon's pattern, a corner that walks back along the edge it came by
  const std::vector<std::array<double, 2>> folded{{0, 0}, {2, 0}, {1, 0}, {2, 1}, {0, 1}};
  write_prism_obj(dir / "folded.obj", folded, {4, 3, 2, 1, 0});
  EXPECT_NE(error_of(surface(dir / "folded.obj", 0.1)).find("is not a simple polygon"), std::string::npos);
  // a corner in the middle of a straight side (a T-junction of a CAD export) is simple
  const std::vector<std::array<double, 2>> straight{{0, 0}, {1, 0}, {2, 0}, {2, 1}, {1, 1}, {0, 1}};
  write_prism_obj(dir / "straight.obj", straight, {5, 4, 3, 2, 1, 0});
  EXPECT_EQ(error_of(surface(dir / "straight.obj", 0.1)), "");
}

// A simple sawtooth outline whose every edge spans the whole width: all pairs of edges overlap, so the
// check would cost corners^2 / 2 predicate calls; it stops at its budget and refuses the file instead.
TEST(Hostile, PolygonFaceTooEntangledToCheckIsRefused) {
  const auto dir = vt::temp_dir();
  std::vector<std::array<double, 2>> saw;
  const int teeth = 2000;  // (2 teeth)^2 / 2 = 8e6 pairs
  for (int i = 0; i <= 2 * teeth; ++i) saw.push_back({1e-3 * i, double(i % 2)});
  saw.push_back({1e-3 * 2 * teeth, -1.0});
  saw.push_back({0.0, -1.0});
  std::vector<int> cap;
  for (int i = int(saw.size()) - 1; i >= 0; --i) cap.push_back(i);
  write_prism_obj(dir / "saw.obj", saw, cap);
  const std::string m = error_of(surface(dir / "saw.obj", 0.5));
  EXPECT_NE(m.find("saw.obj: the polygon faces' edges overlap in more than 5000000 pairs"), std::string::npos) << m;
}

// A fuzzed OBJ (fuzz/regressions/obj/refused_fuzz_polygon_turning_back_broke_the_mesh.obj) with a
// pentagon whose outline walks back along itself (two corners 1 ulp apart): CGAL split it into triangles
// that no longer formed a valid mesh, its repair of degenerate faces then left a 4-corner face, and
// copying that as a triangle overflowed the face array (heap corruption under ASan, SIGSEGV in
// `varsph sample`). The outline is refused before CGAL's triangulation; the mesh is also checked to be
// valid after each of CGAL's steps.
TEST(Hostile, PolygonTurningBackOnItselfIsRefusedBeforeItBreaksTheMesh) {
  const auto dir = vt::temp_dir();
  std::filesystem::copy_file(std::filesystem::path(VARSPH_SOURCE_DIR) / "fuzz" / "regressions" / "obj" /
                                 "refused_fuzz_polygon_turning_back_broke_the_mesh.obj",
                             dir / "folded.obj");
  const std::string m = error_of(surface(dir / "folded.obj", 0.25));
  EXPECT_NE(m.find("folded.obj: a polygon face of 5 corners (the first at 3.22 1 0.55) is not a simple polygon"),
            std::string::npos) << m;
}
