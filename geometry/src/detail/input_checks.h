#pragma once
// Internal: cheap checks of a mesh file and its vertices, made before anything allocates from what the
// file declares or samples from what it holds (docs/geometry.md, "Hostile input"). Each throws
// GeometryError naming the file, what is wrong and what was expected.
#include <cstddef>
#include <filesystem>
#include <string>

namespace varsph::geometry::detail {

// Largest |coordinate| [m] accepted after the transform: beyond it no SPH domain can be meant and the
// lattice arithmetic of the samplers (int cell counts) would overflow.
constexpr double kMaxCoordinate = 1e9;

// Counts a file declares in its header (binary STL triangle count, OFF vertex/face counts, PLY element
// counts) against what its size can hold, so a damaged header cannot make a reader allocate gigabytes.
// ext is the lower-case extension with the dot (".stl", ".off", ".ply"; others are not checked).
void check_declared_counts(const std::filesystem::path& path, const std::string& ext);

// Sum of the triangle areas of a binary STL after the linear part A (row-major 3 x 3) of the transform,
// read straight from the file's records; -1 for an ASCII STL. Lets a surface fill's particle estimate
// refuse a huge soup before CGAL's reader (which merges every vertex in an ordered map) runs.
double binary_stl_area(const std::filesystem::path& path, const double A[9]);

// Every coordinate of n points (x, y, z interleaved) finite and, if `bounded`, within kMaxCoordinate;
// `stage` says where in the pipeline ("in the file", "after the transform") for the message.
void check_coordinates(const std::filesystem::path& path, const double* xyz, std::size_t n, bool bounded,
                       const char* stage);

}  // namespace varsph::geometry::detail
