// The same cube written as ASCII STL, binary STL, OBJ, OFF and PLY gives the same particles;
// a transform scales/moves them.
#include "test_helpers.h"
#include "varsph/geometry/sample_body.h"

using namespace varsph::geometry;

TEST(Formats, AllReadersGiveTheSameParticles) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  vt::write_stl_ascii(dir / "cube_ascii.stl", V, F);
  vt::write_stl_binary(dir / "cube_binary.STL", V, F);
  vt::write_obj(dir / "cube.obj", V, F);
  vt::write_off(dir / "cube.off", V, F);
  vt::write_ply(dir / "cube.ply", V, F);
  vt::MatrixXd ref_s, ref_v;
  for (const char* name : {"cube.off", "cube_ascii.stl", "cube_binary.STL", "cube.obj", "cube.ply"}) {
    BodyRequest r;
    r.mesh = dir / name;
    r.spacing = 0.1;
    r.layers = 2;
    const SampledBody s = sample_body(r);
    r.fill = "volume";
    const SampledBody v = sample_body(r);
    const vt::MatrixXd S = vt::sorted_rows(s.positions), Vv = vt::sorted_rows(v.positions);
    EXPECT_NEAR(s.surface_measure, 6.0, 1e-9) << name;
    if (ref_s.size() == 0) { ref_s = S; ref_v = Vv; continue; }
    ASSERT_EQ(S.rows(), ref_s.rows()) << name;
    ASSERT_EQ(Vv.rows(), ref_v.rows()) << name;
    EXPECT_LT((S - ref_s).cwiseAbs().maxCoeff(), 1e-9) << name;
    EXPECT_LT((Vv - ref_v).cwiseAbs().maxCoeff(), 1e-9) << name;
  }
}

TEST(Formats, TransformIsApplied) {
  const auto dir = vt::temp_dir();
  vt::MatrixXd V; vt::MatrixXi F;
  vt::cube(1.0, V, F);
  vt::write_off(dir / "cube.off", V, F);
  BodyRequest r;
  r.mesh = dir / "cube.off";
  r.spacing = 0.1;
  r.fill = "volume";
  r.transform << 2, 0, 0, 10,  //
                 0, 1, 0, 0,   //
                 0, 0, 0.5, -1, //
                 0, 0, 0, 1;
  const SampledBody b = sample_body(r);
  EXPECT_NEAR(b.enclosed_measure, 1.0, 1e-12);
  EXPECT_EQ(b.positions.rows(), 20 * 10 * 5);
  EXPECT_NEAR(b.positions.col(0).minCoeff(), 10.05, 1e-9);
  EXPECT_NEAR(b.positions.col(2).maxCoeff(), -0.55, 1e-9);
}
