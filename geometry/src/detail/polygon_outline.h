#pragma once
// Internal: the outline of a polygon face, checked before CGAL's triangulate_faces splits it
// (docs/geometry.md, "Hostile input").
//
// CGAL 5.5 splits a face of five or more corners by projecting it along its normal and inserting its
// edges as constraints of a 2D constrained Delaunay triangulation (Exact_intersections_tag), then keeps
// the triangles inside the outline. Two edges that cross make it construct their intersection point,
// which the inexact-constructions kernel rounds: on a fuzzed OBJ hexagon that insertion did not end
// (> 290 s). An outline that touches itself or turns back on itself (a fuzzed pentagon with two corners
// 1 ulp apart) was split into triangles whose edges no longer formed a valid mesh. CGAL refuses a
// crossing outline in any case (its triangulation then has more vertices than the face has corners),
// so every outline that is not simple in CGAL's projection is refused here first, with CGAL's own
// exact predicates; simple ones, convex or not, with straight-through corners or not, go on to CGAL.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cstddef>
#include <vector>

namespace varsph::geometry::detail {

using OutlineKernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// Pairs of edges whose extents overlap that one file may make us test (0.5 s at 100 ns a pair, the rate
// measured under load): simple polygons
// need a few per edge; only outlines folded back and forth across themselves come near it.
constexpr std::size_t kOutlinePairBudget = 5'000'000;

enum class Outline { simple, not_simple, over_budget };

// Whether the closed outline `corners`, seen along `normal` (the face normal CGAL projects with), is
// simple: no two edges that are not neighbours meet (cross or touch), no edge has zero length and no two
// neighbours overlap (the outline turning back at their corner). `budget` counts down the pair tests.
Outline check_outline(const std::vector<OutlineKernel::Point_3>& corners, const OutlineKernel::Vector_3& normal,
                      std::size_t& budget);

}  // namespace varsph::geometry::detail
