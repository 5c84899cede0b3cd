// SPDX-License-Identifier: MIT
// Most kept parts of the drill's crossed faces are quads, whose triangles quad_triangles works
// out directly (core/src/ops/drill/rim_faces.h): wherever it answers, the answer is the general
// path's (ear clipping by kRimTriangulation, then Lawson flips) to the triangle and the corner,
// on convex, concave, nearly cocircular and nearly flat quads at scales and offsets far apart.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "geometry/delaunay_flip.h"
#include "geometry/polygon_triangulation.h"
#include "ops/drill/rim_faces.h"
#include "ops/drill/rim_insertion.h"

namespace deepcut::drill {
namespace {

using geometry::LocalTri;
using P = glm::dvec2;
constexpr double kTau = 6.283185307179586;

// What add_polygon's general path makes of the quad 0-1-2-3 before refining.
std::vector<LocalTri> general_path(const std::array<P, 4>& quad) {
  std::vector<P> q(quad.begin(), quad.end());
  std::vector<LocalTri> clipped;
  geometry::triangulate_polygon(q, {0, 1, 2, 3}, {}, kRimTriangulation, clipped);
  geometry::FlipTriangulation ft;
  ft.reset(q, clipped);
  ft.make_delaunay();
  return ft.triangles();
}

// Counter-clockwise quads of four kinds, each at a random scale and offset.
std::array<P, 4> random_quad(std::mt19937& rng, int kind) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::array<P, 4> q;
  // Four angles in increasing order round a circle (convex, kind 0), on one circle exactly as
  // far as rounding goes (kind 1), with one corner pulled inside (concave, kind 2), or with a
  // corner on the chord of its neighbours (nearly flat, kind 3).
  double angle[4];
  for (double& a : angle) a = kTau * unit(rng);
  std::sort(std::begin(angle), std::end(angle));
  for (int k = 0; k < 4; ++k) {
    const double r = kind == 1 ? 1.0 : 0.5 + unit(rng);
    q[k] = P(r * std::cos(angle[k]), r * std::sin(angle[k]));
  }
  if (kind == 2) q[2] = 0.5 * (q[1] + q[3]) + 0.3 * unit(rng) * (0.5 * (q[1] + q[3]) - q[2]);
  if (kind == 3) q[2] = 0.5 * (q[1] + q[3]) + 1e-14 * (unit(rng) - 0.5) * (q[1] - q[3]);
  const double scale = std::pow(10.0, -4.0 + 6.0 * unit(rng));
  const P offset(std::pow(10.0, 4.0 * unit(rng)) * (unit(rng) - 0.5), 100.0 * (unit(rng) - 0.5));
  for (P& p : q) p = offset + scale * p;
  return q;
}

TEST(DrillRimQuads, DirectTrianglesAreTheGeneralPaths) {
  std::mt19937 rng(1234);
  int answered[4] = {0, 0, 0, 0}, flipped = 0;
  constexpr int kPerKind = 5000;
  for (int kind = 0; kind < 4; ++kind)
    for (int n = 0; n < kPerKind; ++n) {
      const std::array<P, 4> quad = random_quad(rng, kind);
      std::array<LocalTri, 2> direct;
      if (!quad_triangles(quad.data(), direct)) continue;
      ++answered[kind];
      const std::vector<LocalTri> general = general_path(quad);
      ASSERT_EQ(general, std::vector<LocalTri>(direct.begin(), direct.end()))
          << "kind " << kind << " quad " << quad[0].x << "," << quad[0].y << " " << quad[1].x << ","
          << quad[1].y << " " << quad[2].x << "," << quad[2].y << " " << quad[3].x << "," << quad[3].y;
      // A flip leaves the second triangle not starting at the first corner left.
      flipped += direct[1][0] != 0 && direct[1][0] != 1;
    }
  // The direct path answers for nearly every convex quad and most concave ones (a corner pulled
  // far enough makes some not simple), and both ways round the flip are met.
  EXPECT_GT(answered[0], kPerKind * 9 / 10);
  EXPECT_GT(answered[2], kPerKind * 3 / 4);
  EXPECT_GT(answered[1] + answered[3], 0);
  EXPECT_GT(flipped, kPerKind / 10);
  EXPECT_LT(flipped, answered[0] + answered[1] + answered[2] + answered[3]);
}

// The count the drill's pinch check trusts (PlanChunk::gaps): a whole clip of a kept part makes
// whole_clip_triangles, with or without holes and with points along an edge, and a clip that
// drops a flat ear makes fewer.
TEST(DrillRimQuads, ClipsThatDropAnEarMakeFewerThanAWholeClip) {
  auto clip = [](const std::vector<P>& q, const std::vector<std::uint32_t>& outer,
                 const std::vector<std::vector<std::uint32_t>>& holes) {
    std::vector<LocalTri> out;
    geometry::triangulate_polygon(q, outer, holes, kRimTriangulation, out);
    return out.size();
  };
  const std::vector<P> ring = {{0, 0}, {4, 0}, {4, 4}, {0, 4}, {1, 1}, {1, 3}, {3, 3}, {3, 1}};
  EXPECT_EQ(clip(ring, {0, 1, 2, 3}, {{4, 5, 6, 7}}), whole_clip_triangles({0, 1, 2, 3}, {{4, 5, 6, 7}}));
  EXPECT_EQ(whole_clip_triangles({0, 1, 2, 3}, {{4, 5, 6, 7}}), 8u);
  const std::vector<P> edge_point = {{0, 0}, {1, 0}, {2, 0}, {2, 2}, {0, 2}};
  EXPECT_EQ(clip(edge_point, {0, 1, 2, 3, 4}, {}), whole_clip_triangles({0, 1, 2, 3, 4}, {}));
  const std::vector<P> flat = {{0, 0}, {1, 0}, {3, 0}, {2, 0}};
  EXPECT_LT(clip(flat, {0, 1, 2, 3}, {}), whole_clip_triangles({0, 1, 2, 3}, {}));
  const std::vector<P> flat_tip = {{0, 0}, {2, 0}, {2, 2}, {2, 1}};
  EXPECT_LT(clip(flat_tip, {0, 1, 2, 3}, {}), whole_clip_triangles({0, 1, 2, 3}, {}));
}

}  // namespace
}  // namespace deepcut::drill
