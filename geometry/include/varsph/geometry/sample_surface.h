#pragma once
#include <Eigen/Core>
#include "varsph/geometry/read_mesh.h"

namespace varsph::geometry {

// Boundary particles on a triangle mesh and on its offset surfaces (3D).
// Method (docs/geometry.md): planar regions (edge-connected coplanar faces) of at least 16 dx^2 get
// a square lattice in their plane, round(extent/dx) cells per axis tiling the region's bounding box
// (spacing dx, stretched by at most 10 %), axes along the region's longest boundary edge; the rest of the surface (curved parts) is covered by dense
// candidates and thinned by deterministic dart throwing whose radius is chosen so that the count
// matches area/dx^2. Layer k is the offset surface at distance k dx (faces pushed along their
// normal, edges and convex vertices swept to cylinders and spheres), sampled the same way.
// Inputs:
//   mesh     oriented triangle mesh
//   dx       spacing [m]
//   layers   number of layers (>= 1)
//   side     +1: layers along the outward normal, -1: against it
// Outputs:
//   X        #N by 3 positions, N  #N by 3 unit outward normals, A  #N area shares [m^2],
//   L        #N layer index
void sample_surface(const TriangleMesh& mesh, double dx, int layers, int side, Eigen::MatrixXd& X,
                    Eigen::MatrixXd& N, Eigen::VectorXd& A, Eigen::VectorXi& L);

}  // namespace varsph::geometry
