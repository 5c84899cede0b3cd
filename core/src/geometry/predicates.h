// SPDX-License-Identifier: MIT
#pragma once
// Planar predicates shared by the triangulators and the operations. Plain double arithmetic
// (no exact fallback): callers that need tolerances scale them by their own lengths. Private
// to core.

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

namespace deepcut::geometry {

/// A triangle of indices into a point list.
using LocalTri = std::array<std::uint32_t, 3>;

/// Twice the signed area of the triangle a, b, c: > 0 when counter-clockwise.
inline double orient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/// > 0 when d lies inside the circle through the counter-clockwise triangle a, b, c.
inline double incircle(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& d) {
  const double adx = a.x - d.x, ady = a.y - d.y, bdx = b.x - d.x, bdy = b.y - d.y, cdx = c.x - d.x,
               cdy = c.y - d.y;
  const double ad = adx * adx + ady * ady, bd = bdx * bdx + bdy * bdy, cd = cdx * cdx + cdy * cdy;
  return adx * (bdy * cd - bd * cdy) - ady * (bdx * cd - bd * cdx) + ad * (bdx * cdy - bdy * cdx);
}

}  // namespace deepcut::geometry
