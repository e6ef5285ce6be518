// Each class of bad input gives its error (naming the file) or its repair note.
#include "test_helpers.h"
#include "varsph/geometry/geometry_error.h"
#include "varsph/geometry/sample_body.h"

using namespace varsph::geometry;

namespace {

BodyRequest req(const std::filesystem::path& p, const std::string& fill = "surface") {
  BodyRequest r;
  r.mesh = p;
  r.fill = fill;
  r.spacing = 0.1;
  return r;
}

// message of the GeometryError thrown by sample_body(r) ("" if none)
std::string error_of(const BodyRequest& r) {
  try {
    sample_body(r);
  } catch (const GeometryError& e) {
    EXPECT_EQ(e.file(), r.mesh);
    return e.what();
  }
  return "";
}

}  // namespace

TEST(BadInput, MissingFile) {
  const auto dir = vt::temp_dir();
  const std::string m = error_of(req(dir / "nope.stl"));
  EXPECT_NE(m.find((dir / "nope.stl").string()), std::string::npos) << m;
  EXPECT_NE(m.find("not found"), std::string::npos) << m;
}

TEST(BadInput, EmptyFile) {
  const auto dir = vt::temp_dir();
  std::ofstream(dir / "empty.obj").close();
  const std::string m = error_of(req(dir / "empty.obj"));
  EXPECT_NE(m.find("empty.obj: mesh file is empty"), std::string::npos) << m;
}

TEST(BadInput, GarbageFile) {
  const auto dir = vt::temp_dir();
  std::ofstream(dir / "junk.off") << "this is not an OFF file\n";
  const std::string m = error_of(req(dir / "junk.off"));
  EXPECT_NE(m.find("junk.off"), std::string::npos) << m;
  EXPECT_FALSE(m.empty());
}

TEST(BadInput, UnsupportedExtension) {
  const auto dir = vt::temp_dir();
  std::ofstream(dir / "mesh.xyz") << "1 2 3\n";
  const std::string m = error_of(req(dir / "mesh.xyz"));
  EXPECT_NE(m.find("mesh.xyz: unsupported mesh file extension '.xyz'"), std::string::npos) << m;
  BodyRequest r = req(dir / "mesh.xyz");
  r.dimension = 2;
  EXPECT_NE(error_of(r).find("unsupported geometry file extension"), std::string::npos);
}

TEST(BadInput, InvalidRequestFields) {
  const auto dir = vt::temp_dir();
  BodyRequest r = req(dir / "a.off");
  r.spacing = -1;
  EXPECT_NE(error_of(r).find("spacing"), std::string::npos);
  r = req(dir / "a.off");
  r.layer_side = "left";
  EXPECT_NE(error_of(r).find("layer_side"), std::string::npos);
  r = req(dir / "a.off");
  r.fill = "solid";
  EXPECT_NE(error_of(r).find("fill"), std::string::npos);
}

TEST(BadInput, NotClosedForVolumeFill) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  vt::MatrixXi F11 = F.topRows(11);  // one triangle missing: 3 border edges
  vt::write_off(dir / "tank.off", V, F11);
  const std::string m = error_of(req(dir / "tank.off", "volume"));
  EXPECT_NE(m.find("tank.off: mesh is not closed (3 border edges); volume fill needs a closed mesh"), std::string::npos) << m;
  // a surface fill of an open mesh is fine
  EXPECT_EQ(error_of(req(dir / "tank.off")), "");
}

TEST(BadInput, DuplicatedVerticesAreMergedAndReported) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  // every triangle gets its own three vertices (36 vertices)
  vt::MatrixXd V2(36, 3); vt::MatrixXi F2(12, 3);
  for (int f = 0; f < 12; ++f)
    for (int c = 0; c < 3; ++c) { V2.row(3 * f + c) = V.row(F(f, c)); F2(f, c) = 3 * f + c; }
  vt::write_off(dir / "dup.off", V2, F2);
  const SampledBody b = sample_body(req(dir / "dup.off", "volume"));
  EXPECT_TRUE(vt::has_note(b.notes, "merged 28 duplicated vertices"));
  EXPECT_EQ(b.positions.rows(), 1000);
}

TEST(BadInput, FlippedOrientationIsRepaired) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  vt::MatrixXi Ff = F;
  Ff.col(1).swap(Ff.col(2));  // all inward
  vt::write_off(dir / "inward.off", V, Ff);
  SampledBody b = sample_body(req(dir / "inward.off"));
  EXPECT_TRUE(vt::has_note(b.notes, "reversed the orientation of 12 faces"));
  EXPECT_NEAR(b.enclosed_measure, 1.0, 1e-12);
  for (int i = 0; i < b.positions.rows(); ++i)
    EXPECT_GT(b.normals.row(i).dot(b.positions.row(i) - Eigen::RowVector3d(0.5, 0.5, 0.5)), 0);
  // one face flipped only: made consistent with the others
  vt::MatrixXi F1 = F;
  std::swap(F1(3, 1), F1(3, 2));
  vt::write_off(dir / "one.off", V, F1);
  b = sample_body(req(dir / "one.off"));
  EXPECT_TRUE(vt::has_note(b.notes, "reversed the orientation of 1 faces"));
  EXPECT_EQ(b.positions.rows(), 600);
}

TEST(BadInput, DegenerateFacesAreRemoved) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  vt::MatrixXi F2(14, 3);
  F2.topRows(12) = F;
  F2.row(12) << 0, 0, 1;  // repeated vertex
  F2.row(13) << 2, 3, 3;
  vt::write_off(dir / "degen.off", V, F2);
  const SampledBody b = sample_body(req(dir / "degen.off", "volume"));
  EXPECT_TRUE(vt::has_note(b.notes, "removed 2 degenerate faces"));
  EXPECT_EQ(b.positions.rows(), 1000);
}

TEST(BadInput, SelfIntersectingMeshRejectedForVolumeFill) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  // two overlapping cubes in one file
  vt::MatrixXd V2(16, 3); vt::MatrixXi F2(24, 3);
  V2.topRows(8) = V;
  V2.bottomRows(8) = V.array() + 0.45;
  F2.topRows(12) = F;
  F2.bottomRows(12) = F.array() + 8;
  vt::write_off(dir / "two.off", V2, F2);
  const std::string m = error_of(req(dir / "two.off", "volume"));
  EXPECT_NE(m.find("two.off: mesh intersects itself"), std::string::npos) << m;
  BodyRequest r = req(dir / "two.off", "volume");
  r.allow_self_intersections = true;
  const SampledBody b = sample_body(r);
  EXPECT_TRUE(vt::has_note(b.notes, "intersects itself"));
  EXPECT_GT(b.positions.rows(), 0);
}

TEST(BadInput, MeshFarLargerThanDomainIsRefusedBeforeSampling) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1000.0, V, F);  // millimetres
  vt::write_off(dir / "mm.off", V, F);
  BodyRequest r = req(dir / "mm.off");
  r.spacing = 100;
  r.domain_min = Eigen::Vector3d(0, 0, 0);
  r.domain_max = Eigen::Vector3d(2, 2, 2);
  const std::string m = error_of(r);
  EXPECT_NE(m.find("mesh bounding box (0, 0, 0) .. (1000, 1000, 1000) m (after the transform) lies outside the "
                   "domain (0, 0, 0) .. (2, 2, 2) m by up to 998"), std::string::npos) << m;
  EXPECT_NE(m.find("millimetres"), std::string::npos) << m;
  // sticking out by less than one spacing is accepted (a tank wall on the domain's edge)
  r.spacing = 0.1;
  r.transform.topLeftCorner<3, 3>() *= 0.00205;  // 2.05 m cube in a 2 m domain
  EXPECT_EQ(error_of(r), "");
  r.transform.topLeftCorner<3, 3>() *= 1.1;  // 2.255 m: 0.255 m out
  EXPECT_NE(error_of(r).find("lies outside the domain"), std::string::npos);
  r.transform = Eigen::Matrix4d::Identity();
  // with the right scale no warning
  r.transform.topLeftCorner<3, 3>() *= 0.001;
  r.spacing = 0.1;
  const SampledBody b = sample_body(r);
  EXPECT_TRUE(b.notes.empty());
  EXPECT_EQ(b.positions.rows(), 600);
}

TEST(BadInput, MalformedPolylineFile) {
  const auto dir = vt::temp_dir();
  std::ofstream(dir / "bad.poly2d") << "0 0\n1 0\n1 one\n";
  BodyRequest r = req(dir / "bad.poly2d");
  r.dimension = 2;
  const std::string m = error_of(r);
  EXPECT_NE(m.find("bad.poly2d: line 3: expected 'x y'"), std::string::npos) << m;
  r.dimension = 3;
  EXPECT_NE(error_of(r).find("describes a 2D body"), std::string::npos);
}

TEST(BadInput, TwoComponentsAreEachOrientedOutward) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  // a tank-like box and a separate small box, the second one written inside out
  vt::MatrixXd V2(16, 3); vt::MatrixXi F2(24, 3);
  V2.topRows(8) = V;
  V2.bottomRows(8) = (V.array() * 0.2 + 2.0).matrix();
  F2.topRows(12) = F;
  vt::MatrixXi Fin = F.array() + 8;
  Fin.col(1).swap(Fin.col(2));
  F2.bottomRows(12) = Fin;
  vt::write_off(dir / "two.off", V2, F2);
  BodyRequest r = req(dir / "two.off", "volume");
  const SampledBody b = sample_body(r);
  EXPECT_NEAR(b.enclosed_measure, 1.0 + 0.008, 1e-12);
  EXPECT_TRUE(vt::has_note(b.notes, "reversed the orientation of 12 faces so that each of the 2 closed components faces outward"));
  r.fill = "surface";
  r.spacing = 0.05;
  const SampledBody s = sample_body(r);
  for (int i = 0; i < s.positions.rows(); ++i) {
    const Eigen::RowVector3d c = s.positions(i, 0) > 1.5 ? Eigen::RowVector3d(2.1, 2.1, 2.1) : Eigen::RowVector3d(0.5, 0.5, 0.5);
    EXPECT_GT(s.normals.row(i).dot(s.positions.row(i) - c), 0);
  }
}
