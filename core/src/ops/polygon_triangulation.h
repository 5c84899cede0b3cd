// SPDX-License-Identifier: MIT
#pragma once
// Triangulation of planar polygons with holes (ear clipping after bridging holes into their
// outer loop). Private to core: used by cut caps and drill bottoms.

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace deepcut::detail {

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

}  // namespace deepcut::detail
