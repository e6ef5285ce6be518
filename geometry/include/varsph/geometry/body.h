#pragma once
// Plain data describing one scene body made from a mesh (BodyRequest) and the particles made from it
// (SampledBody). Eigen and the standard library only: no CGAL type appears here.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace varsph::geometry {

struct BodyRequest {
  // Resolved path of the geometry file.
  //   dimension 3: triangle/polygon mesh, .stl (ASCII or binary), .obj, .off, .ply
  //   dimension 2: .poly2d polyline file (see docs/geometry.md), or a 3D mesh (extensions above)
  //                cut by the plane `section_point`/`section_normal`
  std::filesystem::path mesh;
  // 2 or 3
  int dimension = 3;
  // "surface": boundary particles on the surface plus `layers - 1` offset layers;
  // "volume" : cell-centred lattice points inside the closed mesh / closed loops.
  std::string fill = "surface";
  // surface fill: total number of layers (1 = surface only, >= 1). Layer k (k = 0 .. layers-1) lies at
  // distance k*spacing from the surface on the side `layer_side`.
  int layers = 1;
  // "outside": layers grow along the outward normal of the closed mesh (a tank that holds fluid
  //            inside it: the extra layers go into the wall material, away from the fluid);
  // "inside" : layers grow against the outward normal (an obstacle with fluid around it).
  // For open meshes / open polylines "outward" is the normal as oriented in the file (3D: right-hand
  // rule of the face winding; 2D: right-hand side of the walking direction).
  std::string layer_side = "outside";
  // particle spacing dx [m], > 0
  double spacing = 0.0;
  // 4 by 4 affine transform applied to the mesh vertices (homogeneous column vectors,
  // x' = transform * [x y z 1]^T) before anything else; in 2D files (x, y) are mapped as (x, y, 0, 1)
  // and the first two rows of the result kept. Units: metres after the transform.
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();

  // dimension 2 with a 3D mesh: the section plane, a point on it [m] and its normal (need not be
  // unit), both applied after `transform`. In-plane coordinates: if the normal is a coordinate axis
  // the two other axes in order (normal y -> (x, z)); otherwise u = normalize(n x e), v = n x u with e
  // the coordinate axis least aligned with n.
  Eigen::Vector3d section_point = Eigen::Vector3d::Zero();
  Eigen::Vector3d section_normal = Eigen::Vector3d::UnitY();

  // volume fill: optional clip box [m] (#dim each; both empty = no clip). Lattice points are
  // (clip_min + (i + 1/2) dx) when a clip box is given, else (mesh bbox min + (i + 1/2) dx).
  Eigen::VectorXd clip_min, clip_max;
  // volume fill: fluid points closer than `exclusion_distance` [m] to any row of
  // `exclusion_points` (#B by dim, e.g. the boundary particles) are removed. Empty = none.
  Eigen::MatrixXd exclusion_points;
  double exclusion_distance = 0.0;

  // optional simulation domain (#dim each; empty = unknown): a mesh whose bounding box (after the
  // transform; for a volume fill within the clip box) sticks out of it by more than one spacing is a
  // GeometryError before sampling (wrong units or transform?).
  Eigen::VectorXd domain_min, domain_max;

  // largest number of particles this body may produce (0 = no limit). Checked before sampling against
  // the estimate surface measure / dx^(dim-1) x layers (surface fill) or enclosed measure / dx^dim
  // (volume fill, within the lattice box); a larger estimate is a GeometryError naming the number.
  double max_particles = 0;

  // volume fill of a self-intersecting mesh is refused unless this is true; then the inside test
  // uses the ray-parity answer of CGAL::Side_of_triangle_mesh and a note says so.
  bool allow_self_intersections = false;
};

struct SampledBody {
  // #N by dim particle positions [m]
  Eigen::MatrixXd positions;
  // #N by dim unit outward normals of the closed mesh (surface fill); 0 by dim for volume fill.
  // For a tank holding fluid inside, the normal pointing into the fluid is -normals.
  Eigen::MatrixXd normals;
  // #N: surface fill: area share [m^2] (3D) / length share [m] (2D) of the particle on its layer;
  //     volume fill : dx^dim
  Eigen::VectorXd measure;
  // #N: 0 on the surface, k on the k-th offset layer (always 0 for volume fill)
  Eigen::VectorXi layer;
  // repairs done and warnings, one sentence each
  std::vector<std::string> notes;
  // of the transformed mesh: area [m^2] and enclosed volume [m^3] in 3D; length [m] and enclosed
  // area [m^2] in 2D (enclosed measure 0 when the mesh/loops are not closed)
  double surface_measure = 0.0;
  double enclosed_measure = 0.0;
};

}  // namespace varsph::geometry
