// SPDX-License-Identifier: MIT
#pragma once
// Invariants of a planar triangulation of polygons with holes, and the loops and triangulations
// they are checked on, shared by the tests of core/src/geometry (header only: the checks need the
// private geometry headers).

#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "geometry/polygon_triangulation.h"
#include "geometry/predicates.h"

namespace deepcut::test {

using Loop = std::vector<std::uint32_t>;

/// Appends the points of `ring` to `pts`; returns their loop.
inline Loop add_loop(std::vector<glm::dvec2>& pts, const std::vector<glm::dvec2>& ring) {
  Loop l;
  for (const glm::dvec2& p : ring) {
    l.push_back(static_cast<std::uint32_t>(pts.size()));
    pts.push_back(p);
  }
  return l;
}

/// A counter-clockwise comb 20 wide and 5 high with ten teeth (one unit wide, four deep) along
/// its top: many reflex corners and ears.
inline std::vector<glm::dvec2> comb_with_ten_teeth() {
  using P = glm::dvec2;
  std::vector<P> ring = {P(0, 0), P(20, 0)};
  for (int t = 9; t >= 0; --t) {
    ring.push_back(P(2 * t + 2, 5));
    ring.push_back(P(2 * t + 1, 5));
    ring.push_back(P(2 * t + 1, 1));
    if (t > 0) ring.push_back(P(2 * t, 1));
  }
  ring.push_back(P(0, 1));
  return ring;
}

/// A star around the origin with `min_corners` + [0, `extra_corners`) corners, radii in
/// [r_min, r_min + r_span], angles jittered within their sectors (draws from `u` on `rng`: the
/// count, then an angle and a radius per corner).
inline std::vector<glm::dvec2> random_star(std::mt19937& rng, std::uniform_real_distribution<double>& u,
                                           int min_corners, int extra_corners, double r_min, double r_span) {
  const int n = min_corners + static_cast<int>(u(rng) * extra_corners);
  std::vector<glm::dvec2> ring;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * geometry::kPi * (i + 0.9 * u(rng)) / n, r = r_min + r_span * u(rng);
    ring.push_back(r * glm::dvec2(std::cos(a), std::sin(a)));
  }
  return ring;
}

/// The outer loop loops[0] with the holes after it, triangulated with the drill's rules
/// (kRimTriangulation in core/src/ops/drill/rim_insertion.h).
inline std::vector<geometry::LocalTri> triangulate_exhaustive(const std::vector<glm::dvec2>& pts,
                                                              const std::vector<Loop>& loops) {
  std::vector<geometry::LocalTri> out;
  geometry::triangulate_polygon(pts, loops[0], {loops.begin() + 1, loops.end()},
                                {geometry::EarSearch::kExhaustive, geometry::HoleBridge::kNearestPair}, out);
  return out;
}

/// Twice the area the loops bound, outer loops counted positive when `sign` is their orientation
/// (+1: counter-clockwise) and holes (the opposite orientation) negative.
inline double region_area2(const std::vector<glm::dvec2>& pts, const std::vector<Loop>& loops, int sign) {
  double a = 0.0;
  for (const Loop& l : loops) a += sign * geometry::signed_area2(pts, l);
  return a;
}

/// Empty when `tris` tiles the region bounded by `loops` (outer loops oriented by `sign`, holes
/// the other way): every triangle has the loops' orientation and positive area, no directed edge
/// is used twice, every loop edge is a triangle edge (so no T-junction on the boundary), every
/// other edge is shared by two triangles, and the areas agree to `area_tol` (relative). With
/// `new_points`, triangles may use points that are on no loop (inserted Steiner points).
inline std::string check_tiling(const std::vector<glm::dvec2>& pts, const std::vector<Loop>& loops,
                                const std::vector<geometry::LocalTri>& tris, int sign, bool new_points = false,
                                double area_tol = 1e-9) {
  std::ostringstream err;
  std::set<std::uint32_t> on_loops;
  std::set<std::pair<std::uint32_t, std::uint32_t>> boundary;
  for (const Loop& l : loops)
    for (std::size_t i = 0; i < l.size(); ++i) {
      on_loops.insert(l[i]);
      const std::uint32_t a = l[i], b = l[(i + 1) % l.size()];
      if (a != b) boundary.insert({a, b});
    }
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> used;
  double area = 0.0;
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const auto& tri = tris[t];
    for (std::uint32_t v : tri)
      if (v >= pts.size() || (!new_points && !on_loops.count(v))) err << "triangle " << t << " uses point " << v << "; ";
    if (!err.str().empty()) return err.str();
    const double o = sign * geometry::orient(pts[tri[0]], pts[tri[1]], pts[tri[2]]);
    if (!(o > 0.0)) err << "triangle " << t << " has area " << o << "; ";
    area += o;
    for (int k = 0; k < 3; ++k) ++used[{tri[k], tri[(k + 1) % 3]}];
  }
  for (const auto& [e, n] : used) {
    if (n > 1) err << "edge " << e.first << "-" << e.second << " used " << n << " times; ";
    if (!boundary.count(e) && !used.count({e.second, e.first}))
      err << "edge " << e.first << "-" << e.second << " is on no loop and has one triangle; ";
  }
  for (const auto& e : boundary)
    if (!used.count(e)) err << "loop edge " << e.first << "-" << e.second << " is no triangle edge; ";
  const double want = region_area2(pts, loops, sign);
  if (std::abs(area - want) > area_tol * std::abs(want)) err << "area " << area << " != " << want << "; ";
  return err.str();
}

}  // namespace deepcut::test
