// SPDX-License-Identifier: MIT
#pragma once
// Geometric predicates shared by the triangulators and the operations: planar orientation,
// circle, crossing and containment tests, and the few distance and angle measures the
// operations take in 2D or 3D. Plain double arithmetic (no exact fallback): callers that need
// tolerances scale them by their own lengths. Private to core.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace deepcut::geometry {

constexpr double kPi = 3.14159265358979323846;

/// A triangle of indices into a point list.
using LocalTri = std::array<std::uint32_t, 3>;

/// The corners of `t` in increasing order: one key for every rotation and reflection of a
/// triangle (for sets and maps of triangles).
inline LocalTri sorted_corners(LocalTri t) {
  std::sort(t.begin(), t.end());
  return t;
}

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

/// Centre of the circle through a, b and c; not finite when they are collinear.
inline glm::dvec2 circumcentre(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  const glm::dvec2 ab = b - a, ac = c - a;
  const double d = 2.0 * (ab.x * ac.y - ab.y * ac.x);
  return a + glm::dvec2(ac.y * glm::dot(ab, ab) - ab.y * glm::dot(ac, ac),
                        ab.x * glm::dot(ac, ac) - ac.x * glm::dot(ab, ab)) /
                 d;
}

/// Whether FlipTriangulation::legalize flips edge a-b of the counter-clockwise triangle a-b-c,
/// with d across it: d inside the circle through a, b, c beyond a tolerance scaled by their
/// spread around d, and the quad c-a-d-b convex (both new triangles counter-clockwise).
inline bool delaunay_flips(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c,
                           const glm::dvec2& d) {
  double scale = 0.0;
  for (const auto* q : {&a, &b, &c}) scale = std::max(scale, glm::dot(*q - d, *q - d));
  if (incircle(a, b, c, d) <= 1e-10 * scale * scale) return false;
  return !(orient(c, a, d) <= 0.0 || orient(d, b, c) <= 0.0);
}

/// The square of the longest edge of triangle a-b-c: the length ear clipping rates an ear by.
inline double longest_edge2(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  return std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
}

/// Ear clipping's quality of an ear of twice-area `turn` and squared longest edge `longest2`
/// (1 for the best shape scale-free; larger is better).
inline double ear_quality(double turn, double longest2) { return turn / std::max(longest2, 1e-300); }

/// The tolerance of the exhaustive ear test for an ear of squared longest edge `longest2`: an
/// area at most this is flat, and a point this far outside an edge still blocks.
inline double ear_tolerance(double longest2) { return 1e-13 * longest2; }

/// Whether p blocks the ear a-b-c in the exhaustive test: inside the closed triangle, widened
/// by `tiny` (ear_tolerance).
inline bool blocks_ear(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& p,
                       double tiny) {
  return orient(a, b, p) >= -tiny && orient(b, c, p) >= -tiny && orient(c, a, p) >= -tiny;
}

/// `x` wrapped to [0, 2 pi).
inline double wrap_2pi(double x) {
  x = std::fmod(x, 2.0 * kPi);
  return x < 0.0 ? x + 2.0 * kPi : x;
}

/// True when the segments a-b and c-d cross at one point interior to both: each segment has the
/// ends of the other strictly on opposite sides. Touching, collinear overlap and shared ends are
/// not crossings.
inline bool segments_cross(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& d) {
  const double d1 = orient(a, b, c), d2 = orient(a, b, d), d3 = orient(c, d, a), d4 = orient(c, d, b);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

/// Twice the signed area of a closed loop of indices into `points` (> 0 when counter-clockwise).
inline double signed_area2(const std::vector<glm::dvec2>& points, const std::vector<std::uint32_t>& loop) {
  double a = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const auto& p = points[loop[i]];
    const auto& q = points[loop[(i + 1) % loop.size()]];
    a += p.x * q.y - q.x * p.y;
  }
  return a;
}

/// Even-odd test of `p` against a closed loop of indices into `pts` (a ray towards +x). Points
/// on the boundary fall either way.
inline bool point_in_loop(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& loop,
                          const glm::dvec2& p) {
  bool inside = false;
  for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
    const auto& a = pts[loop[i]];
    const auto& b = pts[loop[j]];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
  }
  return inside;
}

/// Winding number of closed loops (indices into `xy`) around `p`: +1 for each counter-clockwise
/// loop around it, -1 for each clockwise one. A point on the boundary gets the number of one side
/// or the other.
inline int winding(const std::vector<glm::dvec2>& xy, const std::vector<std::vector<std::uint32_t>>& loops,
                   const glm::dvec2& p) {
  int w = 0;
  for (const auto& l : loops)
    for (std::size_t i = 0; i < l.size(); ++i) {
      const glm::dvec2 &a = xy[l[i]], &b = xy[l[(i + 1) % l.size()]];
      if (a.y <= p.y) {
        if (b.y > p.y && orient(a, b, p) > 0.0) ++w;
      } else if (b.y <= p.y && orient(a, b, p) < 0.0) {
        --w;
      }
    }
  return w;
}

/// Squared distance from `p` to the segment a-b (2D or 3D); a zero-length segment is its point.
template <glm::length_t L>
double segment_distance2(const glm::vec<L, double>& p, const glm::vec<L, double>& a, const glm::vec<L, double>& b) {
  const glm::vec<L, double> e = b - a;
  const double t = std::clamp(glm::dot(p - a, e) / std::max(glm::dot(e, e), 1e-300), 0.0, 1.0);
  const glm::vec<L, double> d = a + t * e - p;
  return glm::dot(d, d);
}

/// Angle at `c` in the triangle (a, b, c), in radians; pi when a or b coincides with c.
inline double angle_at(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 u = a - c, v = b - c;
  const double lu = glm::length(u), lv = glm::length(v);
  if (!(lu > 0.0) || !(lv > 0.0)) return kPi;
  return std::acos(std::clamp(glm::dot(u, v) / (lu * lv), -1.0, 1.0));
}

}  // namespace deepcut::geometry
