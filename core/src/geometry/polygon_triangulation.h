// SPDX-License-Identifier: MIT
#pragma once
// Triangulation of planar polygons with holes (ear clipping after bridging holes into their
// outer loop). Private to core: used by cut caps and by the drill's rim faces and walls.

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "geometry/predicates.h"

namespace deepcut::geometry {

/// Triangulates the region bounded by `loops` (2D points, each loop a closed polygon given by
/// indices into `points`). Loops whose signed area has the sign of `outer_sign` (+1: counter-
/// clockwise) are outer boundaries; the others are holes, assigned to the smallest outer loop
/// containing them. Output triangles have the orientation of the outer loops and index `points`.
/// Degenerate input (zero-area loops, self-touching loops) is handled best-effort: no triangle
/// is emitted twice and the output never references a point outside the loops.
std::vector<std::array<std::uint32_t, 3>> triangulate_loops(const std::vector<glm::dvec2>& points,
                                                             const std::vector<std::vector<std::uint32_t>>& loops,
                                                             int outer_sign);

/// Twice the signed area of a loop (positive when counter-clockwise).
double signed_area2(const std::vector<glm::dvec2>& points, const std::vector<std::uint32_t>& loop);

/// Ear clipping of one counter-clockwise, weakly simple polygon (indices into `pts`; a bridged
/// hole repeats two points), appending to `out`. An ear must have positive area and no other
/// polygon point in its closed triangle (with a tolerance relative to the ear's longest edge), so
/// points on a diagonal never make T-junctions. Best-shaped ears first, every corner re-examined
/// after each clip.
void clip_polygon(const std::vector<glm::dvec2>& pts, std::vector<std::uint32_t> poly, std::vector<LocalTri>& out);

/// Joins a clockwise `hole` lying inside the counter-clockwise `outer` into one weakly simple
/// polygon. A hole sharing a point with `outer` is spliced in there; otherwise the bridge is the
/// shortest outer-hole segment that crosses no edge of `outer`, `hole` or `others`.
std::vector<std::uint32_t> bridge(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& outer,
                                  const std::vector<std::uint32_t>& hole,
                                  const std::vector<std::vector<std::uint32_t>>& others = {});

/// Triangulates a counter-clockwise outer loop `loops[0]` with at most one clockwise hole
/// `loops[1]` inside it (bridge, then clip_polygon).
std::vector<LocalTri> triangulate(const std::vector<glm::dvec2>& pts, const std::vector<std::vector<std::uint32_t>>& loops);

}  // namespace deepcut::geometry

namespace deepcut::detail {
using geometry::signed_area2;  // the name drill.cpp's walls call
}  // namespace deepcut::detail
