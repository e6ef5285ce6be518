#pragma once
// Internal: the outline of a polygon face, checked before CGAL's triangulate_faces splits it
// (docs/geometry.md, "Hostile input").
//
// CGAL 5.5 splits a face of five or more corners by projecting it along its normal and inserting its
// edges as constraints of a 2D constrained Delaunay triangulation (Exact_intersections_tag). Two edges
// that cross make it construct their intersection point, which the inexact-constructions kernel rounds;
// on a fuzzed OBJ hexagon that insertion did not end (> 290 s). CGAL refuses such a face in any case
// (its triangulation then has more vertices than the face has corners), so refusing it first, with the
// same projection and CGAL's exact orientation predicate, changes no result and removes the hang.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cstddef>
#include <vector>

namespace varsph::geometry::detail {

using OutlineKernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// Pairs of edges whose extents overlap that one file may make us test (0.5 s at 100 ns a pair, the rate
// measured under load): simple polygons
// need a few per edge; only outlines folded back and forth across themselves come near it.
constexpr std::size_t kOutlinePairBudget = 5'000'000;

enum class Outline { simple, crosses, over_budget };

// Whether two non-adjacent edges of the closed outline `corners` cross at a point inside both, seen
// along `normal` (the face normal CGAL projects with). `budget` counts down the pair tests made.
Outline check_outline(const std::vector<OutlineKernel::Point_3>& corners, const OutlineKernel::Vector_3& normal,
                      std::size_t& budget);

}  // namespace varsph::geometry::detail
