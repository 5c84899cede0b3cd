// SPDX-License-Identifier: MIT
#include "geometry/delaunay_flip.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "geometry/polygon_triangulation.h"
#include "planar_checks.h"

namespace deepcut::geometry {
namespace {

using test::add_loop;
using test::check_tiling;
using test::comb_with_ten_teeth;
using test::Loop;
using test::random_star;
using test::triangulate_exhaustive;
using P = glm::dvec2;
constexpr double kTau = 6.283185307179586;

// incircle scaled to be dimensionless: > tol means clearly inside the circumcircle.
double incircle_rel(const P& a, const P& b, const P& c, const P& d) {
  double scale = 0.0;
  for (const P& q : {a, b, c}) scale = std::max(scale, glm::dot(q - d, q - d));
  return incircle(a, b, c, d) / std::max(scale * scale, 1e-300);
}

// Every edge shared by two triangles is locally Delaunay: the point across it is not inside the
// circumcircle (beyond a relative tolerance), or the two triangles form a non-convex quad.
std::string check_locally_delaunay(const std::vector<P>& pts, const std::vector<LocalTri>& tris) {
  std::string err;
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tris[t][k], b = tris[t][(k + 1) % 3], c = tris[t][(k + 2) % 3];
      for (const LocalTri& u : tris)
        for (int m = 0; m < 3; ++m) {
          if (u[m] != b || u[(m + 1) % 3] != a) continue;
          const std::uint32_t d = u[(m + 2) % 3];
          const bool convex = orient(pts[c], pts[a], pts[d]) > 0.0 && orient(pts[d], pts[b], pts[c]) > 0.0;
          if (convex && incircle_rel(pts[a], pts[b], pts[c], pts[d]) > 1e-9)
            err += "edge " + std::to_string(a) + "-" + std::to_string(b) + " is not Delaunay; ";
        }
    }
  return err;
}

std::set<std::pair<std::uint32_t, std::uint32_t>> undirected_edges(const std::vector<LocalTri>& tris) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> e;
  for (const LocalTri& t : tris)
    for (int k = 0; k < 3; ++k) e.insert({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  return e;
}

TEST(DelaunayFlip, FlipsTheLongDiagonalOfAKite) {
  std::vector<P> pts = {P(0, 0), P(1, -0.2), P(2, 0), P(1, 0.2)};
  FlipTriangulation ft(pts, {{0, 1, 2}, {0, 2, 3}});
  EXPECT_TRUE(ft.is_interior(0, 2));
  EXPECT_NE(check_locally_delaunay(pts, ft.triangles()), "");
  ft.make_delaunay();
  EXPECT_EQ(check_locally_delaunay(pts, ft.triangles()), "");
  const auto edges = undirected_edges(ft.triangles());
  EXPECT_TRUE(edges.count({1, 3}));
  EXPECT_FALSE(edges.count({0, 2}));
  EXPECT_TRUE(ft.is_interior(1, 3) || ft.is_interior(3, 1));
  EXPECT_EQ(check_tiling(pts, {{0, 1, 2, 3}}, ft.triangles(), 1), "");
}

TEST(DelaunayFlip, InsertedPointsInAConvexHullGiveTheDelaunayTriangulation) {
  std::vector<P> pts;
  const Loop square = add_loop(pts, {P(0, 0), P(1, 0), P(1, 1), P(0, 1)});
  FlipTriangulation ft(pts, triangulate_exhaustive(pts, {square}));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.01, 0.99);
  const int inserted = 200;
  for (int i = 0; i < inserted; ++i) EXPECT_TRUE(ft.insert(P(u(rng), u(rng))));
  ASSERT_EQ(pts.size(), 4u + inserted);  // insert() appends to the caller's points
  const auto& tris = ft.triangles();
  EXPECT_EQ(tris.size(), 2u + 2u * inserted);
  EXPECT_EQ(check_tiling(pts, {square}, tris, 1, true), "");
  // Empty circumcircles: no point is inside any triangle's circle (the points are in general
  // position, so this is the one Delaunay triangulation).
  for (const LocalTri& t : tris)
    for (std::uint32_t v = 0; v < pts.size(); ++v) {
      if (v == t[0] || v == t[1] || v == t[2]) continue;
      EXPECT_LE(incircle_rel(pts[t[0]], pts[t[1]], pts[t[2]], pts[v]), 1e-9);
    }
}

TEST(DelaunayFlip, ConstrainedEdgesAreKept) {
  // A comb: the Delaunay flips may not cut across its teeth.
  const std::vector<P> ring = comb_with_ten_teeth();
  std::vector<P> pts;
  const Loop comb = add_loop(pts, ring);
  std::vector<LocalTri> tris;
  clip_ears(pts, comb, EarSearch::kExhaustive, tris);
  FlipTriangulation ft(pts, tris);
  ft.make_delaunay();
  EXPECT_EQ(check_tiling(pts, {comb}, ft.triangles(), 1), "");  // every loop edge still there
  EXPECT_EQ(ft.triangles().size(), ring.size() - 2);
  EXPECT_EQ(check_locally_delaunay(pts, ft.triangles()), "");
  for (std::size_t i = 0; i < comb.size(); ++i) EXPECT_FALSE(ft.is_interior(comb[i], comb[(i + 1) % comb.size()]));
}

TEST(DelaunayFlip, PolygonWithAHole) {
  std::vector<P> pts;
  std::vector<P> outer, hole;
  for (int i = 0; i < 24; ++i) outer.push_back(10.0 * P(std::cos(kTau * i / 24), std::sin(kTau * i / 24)));
  for (int i = 0; i < 7; ++i) hole.push_back(P(2, 1) + 3.0 * P(std::cos(-kTau * i / 7), std::sin(-kTau * i / 7)));
  const std::vector<Loop> loops = {add_loop(pts, outer), add_loop(pts, hole)};
  FlipTriangulation ft(pts, triangulate_exhaustive(pts, loops));
  ft.make_delaunay();
  EXPECT_EQ(check_tiling(pts, loops, ft.triangles(), 1), "");
  EXPECT_EQ(ft.triangles().size(), 24u + 7u + 2u - 2u);
  EXPECT_EQ(check_locally_delaunay(pts, ft.triangles()), "");
  // Points in the hole or outside are refused; points in the region are taken.
  const std::size_t before = ft.triangles().size();
  EXPECT_FALSE(ft.insert(P(2, 1)));
  EXPECT_FALSE(ft.insert(P(20, 0)));
  EXPECT_EQ(ft.triangles().size(), before);
  EXPECT_EQ(pts.size(), 31u);
  EXPECT_TRUE(ft.insert(P(-6, -2)));
  EXPECT_TRUE(ft.insert(P(0, 8)));
  EXPECT_EQ(ft.triangles().size(), before + 4);
  EXPECT_EQ(check_tiling(pts, loops, ft.triangles(), 1, true), "");
  EXPECT_EQ(check_locally_delaunay(pts, ft.triangles()), "");
}

TEST(DelaunayFlip, PointsOnEdgesOrVerticesAreRefused) {
  std::vector<P> pts = {P(0, 0), P(2, 0), P(2, 2), P(0, 2)};
  FlipTriangulation ft(pts, {{0, 1, 2}, {0, 2, 3}});
  EXPECT_FALSE(ft.insert(P(1, 1)));  // on the diagonal
  EXPECT_FALSE(ft.insert(P(1, 0)));  // on the boundary
  EXPECT_FALSE(ft.insert(P(2, 2)));  // a vertex
  EXPECT_EQ(ft.triangles().size(), 2u);
  EXPECT_EQ(pts.size(), 4u);
  EXPECT_FALSE(ft.is_interior(0, 1));
  EXPECT_TRUE(ft.is_interior(0, 2));
  EXPECT_TRUE(ft.is_interior(2, 0));
  EXPECT_FALSE(ft.is_interior(1, 3));  // not an edge
}

TEST(DelaunayFlip, CocircularPointsTerminate) {
  // A regular 16-gon: every point on one circle, every diagonal as Delaunay as another.
  std::vector<P> pts;
  std::vector<P> ring;
  for (int i = 0; i < 16; ++i) ring.push_back(P(std::cos(kTau * i / 16), std::sin(kTau * i / 16)));
  const Loop loop = add_loop(pts, ring);
  FlipTriangulation ft(pts, triangulate_exhaustive(pts, {loop}));
  ft.make_delaunay();
  EXPECT_EQ(check_tiling(pts, {loop}, ft.triangles(), 1), "");
  EXPECT_EQ(ft.triangles().size(), 14u);
}

TEST(DelaunayFlip, NeedleStripStaysValid) {
  // A strip 1e-6 wide with staggered points on both sides: every triangle is a needle.
  std::vector<P> ring;
  for (int i = 0; i <= 30; ++i) ring.push_back(P(i, 0));
  for (int i = 30; i >= 0; --i) ring.push_back(P(i + 0.5, 1e-6));
  std::vector<P> pts;
  const Loop strip = add_loop(pts, ring);
  FlipTriangulation ft(pts, triangulate_exhaustive(pts, {strip}));
  ft.make_delaunay();
  EXPECT_EQ(check_tiling(pts, {strip}, ft.triangles(), 1), "");
  EXPECT_EQ(ft.triangles().size(), ring.size() - 2);
  EXPECT_EQ(check_locally_delaunay(pts, ft.triangles()), "");
}

TEST(DelaunayFlip, RandomStarsAfterFlipsAndInsertions) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 100; ++trial) {
    // Radii in [0.5, 1], angles jittered within 12 or more sectors: every edge stays farther than
    // 0.44 from the origin.
    const std::vector<P> ring = random_star(rng, u, 12, 30, 0.5, 0.5);
    const int n = static_cast<int>(ring.size());
    std::vector<P> pts;
    const Loop loop = add_loop(pts, ring);
    FlipTriangulation ft(pts, triangulate_exhaustive(pts, {loop}));
    ft.make_delaunay();
    EXPECT_EQ(check_tiling(pts, {loop}, ft.triangles(), 1), "") << "trial " << trial;
    EXPECT_EQ(check_locally_delaunay(pts, ft.triangles()), "") << "trial " << trial;
    int inserted = 0;
    for (int i = 0; i < 20; ++i) {
      const double a = kTau * u(rng), r = 0.4 * std::sqrt(u(rng));
      inserted += ft.insert(r * P(std::cos(a), std::sin(a))) ? 1 : 0;
    }
    EXPECT_EQ(inserted, 20) << "trial " << trial;
    EXPECT_EQ(ft.triangles().size(), static_cast<std::size_t>(n - 2 + 2 * inserted)) << "trial " << trial;
    EXPECT_EQ(check_tiling(pts, {loop}, ft.triangles(), 1, true), "") << "trial " << trial;
    EXPECT_EQ(check_locally_delaunay(pts, ft.triangles()), "") << "trial " << trial;
  }
}

}  // namespace
}  // namespace deepcut::geometry
