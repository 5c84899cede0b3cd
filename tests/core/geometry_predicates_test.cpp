// SPDX-License-Identifier: MIT
#include "geometry/predicates.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace deepcut::geometry {
namespace {

using P = glm::dvec2;

TEST(GeometryPredicates, OrientSignAndSymmetry) {
  const P a(0, 0), b(4, 0), c(1, 3);
  EXPECT_GT(orient(a, b, c), 0.0);  // counter-clockwise
  EXPECT_LT(orient(a, c, b), 0.0);
  EXPECT_DOUBLE_EQ(orient(a, b, c), 12.0);  // twice the area
  // Cyclic shifts keep the sign and value, swaps negate it (exact on small integers).
  EXPECT_EQ(orient(a, b, c), orient(b, c, a));
  EXPECT_EQ(orient(a, b, c), orient(c, a, b));
  EXPECT_EQ(orient(a, b, c), -orient(b, a, c));
  // Translation does not change it (exact on integers).
  const P t(1000, -7);
  EXPECT_EQ(orient(a + t, b + t, c + t), orient(a, b, c));
}

TEST(GeometryPredicates, OrientCollinearAndDegenerate) {
  EXPECT_EQ(orient(P(0, 0), P(1, 1), P(5, 5)), 0.0);
  EXPECT_EQ(orient(P(0, 0), P(1, 1), P(-3, -3)), 0.0);  // collinear outside the segment
  EXPECT_EQ(orient(P(2, 3), P(2, 3), P(7, -1)), 0.0);   // repeated point
  EXPECT_EQ(orient(P(2, 3), P(2, 3), P(2, 3)), 0.0);
  // A needle: the third point a hair off the line still has the right sign.
  EXPECT_GT(orient(P(0, 0), P(1, 0), P(1e6, 1e-300)), 0.0);
  EXPECT_LT(orient(P(0, 0), P(1, 0), P(0.5, -1e-12)), 0.0);
}

TEST(GeometryPredicates, IncircleInsideOutsideAndCocircular) {
  // (+-5, 0), (0, +-5), (3, 4) all lie on the circle of radius 5: incircle is exactly 0.
  const P a(5, 0), b(0, 5), c(-5, 0);
  ASSERT_GT(orient(a, b, c), 0.0);
  EXPECT_EQ(incircle(a, b, c, P(0, -5)), 0.0);
  EXPECT_EQ(incircle(a, b, c, P(3, 4)), 0.0);
  EXPECT_EQ(incircle(a, b, c, P(-4, -3)), 0.0);
  EXPECT_GT(incircle(a, b, c, P(0, 0)), 0.0);
  EXPECT_GT(incircle(a, b, c, P(4.9, 0)), 0.0);
  EXPECT_LT(incircle(a, b, c, P(5.1, 0)), 0.0);
  EXPECT_LT(incircle(a, b, c, P(100, 100)), 0.0);
  // The sign does not depend on which corner starts the counter-clockwise triangle.
  for (const P d : {P(1, 1), P(6, 0), P(0, -5)}) {
    EXPECT_EQ(incircle(a, b, c, d) > 0, incircle(b, c, a, d) > 0);
    EXPECT_EQ(incircle(a, b, c, d) < 0, incircle(c, a, b, d) < 0);
  }
  // A clockwise triangle flips the sign.
  EXPECT_LT(incircle(a, c, b, P(0, 0)), 0.0);
}

TEST(GeometryPredicates, IncircleAgreesWithDistanceToCircumcentre) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    P a(u(rng), u(rng)), b(u(rng), u(rng)), c(u(rng), u(rng));
    const P d(u(rng), u(rng));
    if (orient(a, b, c) < 0) std::swap(b, c);
    const double o = orient(a, b, c);
    if (o < 1.0) continue;  // skip slivers: the circumcentre is ill-conditioned there
    // Circumcentre by the textbook formula.
    const double aa = glm::dot(a, a), bb = glm::dot(b, b), cc = glm::dot(c, c);
    const P centre((aa * (b.y - c.y) + bb * (c.y - a.y) + cc * (a.y - b.y)) / (2 * o),
                   (aa * (c.x - b.x) + bb * (a.x - c.x) + cc * (b.x - a.x)) / (2 * o));
    const double r = glm::length(a - centre), dist = glm::length(d - centre);
    if (std::abs(dist - r) < 1e-6 * r) continue;
    EXPECT_EQ(incircle(a, b, c, d) > 0, dist < r) << i;
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(GeometryPredicates, SegmentsCrossProperOnly) {
  EXPECT_TRUE(segments_cross(P(0, 0), P(2, 2), P(0, 2), P(2, 0)));
  EXPECT_FALSE(segments_cross(P(0, 0), P(1, 1), P(3, 0), P(2, 1)));  // apart
  EXPECT_FALSE(segments_cross(P(0, 0), P(2, 0), P(0, 1), P(2, 1)));  // parallel
  EXPECT_FALSE(segments_cross(P(0, 0), P(2, 0), P(2, 0), P(3, 5)));  // shared end
  EXPECT_FALSE(segments_cross(P(0, 0), P(2, 0), P(1, 0), P(1, 5)));  // T: an end on the other
  EXPECT_FALSE(segments_cross(P(0, 0), P(2, 0), P(1, 0), P(3, 0)));  // collinear overlap
  EXPECT_FALSE(segments_cross(P(0, 0), P(2, 0), P(0, 0), P(2, 0)));  // the same segment
  EXPECT_FALSE(segments_cross(P(1, 1), P(1, 1), P(0, 0), P(2, 2)));  // a point on a segment
  // A needle crossing a needle.
  EXPECT_TRUE(segments_cross(P(0, -1e-9), P(1, 1e-9), P(0, 1e-9), P(1, -1e-9)));
}

TEST(GeometryPredicates, SegmentsCrossSymmetric) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> u(-4, 4);  // small integers: many touching and collinear cases
  for (int i = 0; i < 5000; ++i) {
    const P a(u(rng), u(rng)), b(u(rng), u(rng)), c(u(rng), u(rng)), d(u(rng), u(rng));
    const bool x = segments_cross(a, b, c, d);
    EXPECT_EQ(x, segments_cross(b, a, c, d));
    EXPECT_EQ(x, segments_cross(a, b, d, c));
    EXPECT_EQ(x, segments_cross(c, d, a, b));
    if (x) {  // a proper crossing: the ends of each segment are strictly apart
      EXPECT_NE(orient(a, b, c), 0.0);
      EXPECT_NE(orient(c, d, a), 0.0);
    }
  }
}

TEST(GeometryPredicates, SignedArea) {
  const std::vector<P> pts = {P(0, 0), P(1, 0), P(1, 1), P(0, 1), P(2, 2), P(3, 3)};
  EXPECT_EQ(signed_area2(pts, {0, 1, 2, 3}), 2.0);
  EXPECT_EQ(signed_area2(pts, {3, 2, 1, 0}), -2.0);
  EXPECT_EQ(signed_area2(pts, {1, 2, 3, 0}), 2.0);  // any starting point
  EXPECT_EQ(signed_area2(pts, {0, 2, 4, 5}), 0.0);  // collinear run
  EXPECT_EQ(signed_area2(pts, {0, 1}), 0.0);        // too short to have area
  EXPECT_EQ(signed_area2(pts, {}), 0.0);
  // A bow tie: its two lobes have opposite orientations and cancel.
  const std::vector<P> bow = {P(0, 0), P(2, 2), P(2, 0), P(0, 2)};
  EXPECT_EQ(signed_area2(bow, {0, 1, 2, 3}), 0.0);
}

TEST(GeometryPredicates, PointInLoopConcave) {
  // A "U": the notch (1..2 x 1..3) is outside.
  const std::vector<P> pts = {P(0, 0), P(3, 0), P(3, 3), P(2, 3), P(2, 1), P(1, 1), P(1, 3), P(0, 3)};
  const std::vector<std::uint32_t> u = {0, 1, 2, 3, 4, 5, 6, 7};
  EXPECT_TRUE(point_in_loop(pts, u, P(0.5, 2.5)));
  EXPECT_TRUE(point_in_loop(pts, u, P(2.5, 2.5)));
  EXPECT_TRUE(point_in_loop(pts, u, P(1.5, 0.5)));
  EXPECT_FALSE(point_in_loop(pts, u, P(1.5, 2.0)));  // in the notch
  EXPECT_FALSE(point_in_loop(pts, u, P(-1, 1)));
  EXPECT_FALSE(point_in_loop(pts, u, P(4, 1)));
  // The orientation does not matter.
  const std::vector<std::uint32_t> reversed(u.rbegin(), u.rend());
  EXPECT_TRUE(point_in_loop(pts, reversed, P(0.5, 2.5)));
  EXPECT_FALSE(point_in_loop(pts, reversed, P(1.5, 2.0)));
  // Horizontal edges at the point's height do not count twice.
  EXPECT_TRUE(point_in_loop(pts, u, P(2.5, 1.0)));
}

TEST(GeometryPredicates, WindingNumbers) {
  const std::vector<P> pts = {P(0, 0), P(4, 0), P(4, 4), P(0, 4), P(1, 1), P(3, 1), P(3, 3), P(1, 3)};
  const std::vector<std::uint32_t> outer = {0, 1, 2, 3}, inner = {4, 5, 6, 7};
  const std::vector<std::uint32_t> outer_cw(outer.rbegin(), outer.rend()), inner_cw(inner.rbegin(), inner.rend());
  EXPECT_EQ(winding(pts, {outer}, P(2, 2)), 1);
  EXPECT_EQ(winding(pts, {outer_cw}, P(2, 2)), -1);
  EXPECT_EQ(winding(pts, {outer}, P(5, 2)), 0);
  EXPECT_EQ(winding(pts, {outer, inner}, P(2, 2)), 2);       // nested, same orientation
  EXPECT_EQ(winding(pts, {outer, inner_cw}, P(2, 2)), 0);    // a hole
  EXPECT_EQ(winding(pts, {outer, inner_cw}, P(0.5, 2)), 1);  // between the loops
  EXPECT_EQ(winding(pts, {}, P(2, 2)), 0);
  // Agrees with the even-odd test on simple loops.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 5.0);
  for (int i = 0; i < 500; ++i) {
    const P p(u(rng), u(rng));
    EXPECT_EQ(winding(pts, {outer}, p) != 0, point_in_loop(pts, outer, p)) << p.x << " " << p.y;
  }
}

TEST(GeometryPredicates, SegmentDistance) {
  using V = glm::dvec3;
  const V a(0, 0, 0), b(4, 0, 0);
  EXPECT_EQ(segment_distance2(V(2, 3, 0), a, b), 9.0);   // above the middle
  EXPECT_EQ(segment_distance2(V(-3, 0, 4), a, b), 25.0);  // beyond an end: to the end point
  EXPECT_EQ(segment_distance2(V(7, 4, 0), a, b), 25.0);
  EXPECT_EQ(segment_distance2(V(1, 0, 0), a, b), 0.0);    // on it
  EXPECT_EQ(segment_distance2(V(1, 2, 2), a, a), 9.0);    // a zero-length segment is its point
  EXPECT_EQ(segment_distance2(V(1, 2, 2), a, b), segment_distance2(V(1, 2, 2), b, a));
  // The planar version agrees with the spatial one in the z = 0 plane.
  EXPECT_EQ(segment_distance2(P(2, 3), P(0, 0), P(4, 0)), 9.0);
  EXPECT_EQ(segment_distance2(P(-3, 4), P(0, 0), P(4, 0)), 25.0);
  // A needle segment: still the distance to its line inside it.
  EXPECT_NEAR(segment_distance2(P(0.5, 1.0), P(0, 0), P(1, 1e-9)), 1.0, 1e-8);
}

TEST(GeometryPredicates, AngleAt) {
  using V = glm::dvec3;
  const double pi = 3.14159265358979323846;
  EXPECT_NEAR(angle_at(V(1, 0, 0), V(0, 1, 0), V(0, 0, 0)), pi / 2, 1e-15);
  EXPECT_NEAR(angle_at(V(1, 0, 0), V(1, 1, 0), V(0, 0, 0)), pi / 4, 1e-15);
  EXPECT_NEAR(angle_at(V(1, 0, 0), V(-1, 0, 0), V(0, 0, 0)), pi, 1e-15);  // straight
  EXPECT_EQ(angle_at(V(1, 0, 0), V(2, 0, 0), V(0, 0, 0)), 0.0);            // collinear, same side
  EXPECT_EQ(angle_at(V(0, 0, 0), V(1, 0, 0), V(0, 0, 0)), pi);             // degenerate corner
  // The angles of a triangle add up to pi, needles included.
  for (const double h : {1.0, 1e-3, 1e-8}) {
    const V a(0, 0, 0), b(1, 0, 0), c(0.3, h, 0.2);
    EXPECT_NEAR(angle_at(b, c, a) + angle_at(c, a, b) + angle_at(a, b, c), pi, 1e-12);
  }
}

}  // namespace
}  // namespace deepcut::geometry
