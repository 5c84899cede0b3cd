// SPDX-License-Identifier: MIT
// Face refinement along inserted points (core/src/ops/common/face_refinement.h): a face split at
// points inside it, on its edges, on sub-edges, on existing points, and along a chord.
#include "ops/common/face_refinement.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace deepcut::detail {
namespace {

const Triangle kFace = {VertexId(10), VertexId(11), VertexId(12)};

// Twice the signed area of a sub-triangle in the face's (bary.y, bary.z) plane, where the face
// itself has area2 1.
double area2(const FaceRefinement& r, const std::array<int, 3>& t) {
  const auto& p = r.points();
  const glm::dvec2 a(p[t[0]].bary.y, p[t[0]].bary.z), b(p[t[1]].bary.y, p[t[1]].bary.z),
      c(p[t[2]].bary.y, p[t[2]].bary.z);
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Every sub-triangle keeps the face's orientation and has area; together they tile the face.
void expect_tiles_the_face(const FaceRefinement& r) {
  double total = 0.0;
  for (const auto& t : r.triangles()) {
    const double a = area2(r, t);
    EXPECT_GT(a, 0.0) << "sub-triangle " << t[0] << " " << t[1] << " " << t[2] << " is flipped or flat";
    total += a;
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  // Each interior sub-edge is used once in each direction, each edge on the face's border once.
  std::multiset<std::pair<int, int>> directed;
  for (const auto& t : r.triangles())
    for (int k = 0; k < 3; ++k) directed.insert({t[k], t[(k + 1) % 3]});
  for (const auto& [a, b] : directed) {
    EXPECT_EQ(directed.count({a, b}), 1u) << "sub-edge " << a << "-" << b << " used twice";
  }
}

bool joined(const FaceRefinement& r, int a, int b) {
  for (const auto& t : r.triangles())
    for (int k = 0; k < 3; ++k)
      if ((t[k] == a && t[(k + 1) % 3] == b) || (t[k] == b && t[(k + 1) % 3] == a)) return true;
  return false;
}

TEST(FaceRefinementTest, starts_as_the_face_itself) {
  const FaceRefinement r(kFace);
  ASSERT_EQ(r.points().size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(r.points()[k].v, kFace[k]);
    EXPECT_EQ(r.points()[k].bary[k], 1.0);
  }
  ASSERT_EQ(r.triangles().size(), 1u);
  EXPECT_EQ(r.triangles()[0], (std::array<int, 3>{0, 1, 2}));
}

TEST(FaceRefinementTest, a_point_inside_splits_the_face_in_three) {
  FaceRefinement r(kFace);
  EXPECT_EQ(r.insert(VertexId(20), {0.2, 0.3, 0.5}), VertexId(20));
  ASSERT_EQ(r.points().size(), 4u);
  EXPECT_EQ(r.triangles().size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(joined(r, k, 3));
  expect_tiles_the_face(r);
}

TEST(FaceRefinementTest, a_point_on_the_face_edge_splits_it_in_two) {
  FaceRefinement r(kFace);
  EXPECT_EQ(r.insert(VertexId(20), {0.0, 0.4, 0.6}), VertexId(20));  // on the edge 1-2
  EXPECT_EQ(r.triangles().size(), 2u);
  EXPECT_TRUE(joined(r, 0, 3));
  EXPECT_FALSE(joined(r, 1, 2));
  expect_tiles_the_face(r);
}

TEST(FaceRefinementTest, a_point_on_a_sub_edge_splits_the_sub_triangles_on_both_sides) {
  FaceRefinement r(kFace);
  r.insert(VertexId(20), {1.0 / 3, 1.0 / 3, 1.0 / 3});
  // Halfway from corner 0 to the centre: on the sub-edge 0-3, between two sub-triangles.
  EXPECT_EQ(r.insert(VertexId(21), {2.0 / 3, 1.0 / 6, 1.0 / 6}), VertexId(21));
  EXPECT_EQ(r.triangles().size(), 5u);
  EXPECT_FALSE(joined(r, 0, 3));
  EXPECT_TRUE(joined(r, 0, 4));
  EXPECT_TRUE(joined(r, 4, 3));
  expect_tiles_the_face(r);
}

TEST(FaceRefinementTest, a_point_on_an_existing_point_is_that_point) {
  FaceRefinement r(kFace);
  EXPECT_EQ(r.insert(VertexId(20), {1.0 - 1e-12, 1e-12, 0.0}), kFace[0]);  // within 1e-9 of corner 0
  EXPECT_EQ(r.points().size(), 3u);
  EXPECT_EQ(r.triangles().size(), 1u);
  r.insert(VertexId(21), {0.25, 0.25, 0.5});
  EXPECT_EQ(r.insert(VertexId(22), {0.25, 0.25, 0.5}), VertexId(21));  // the same place twice
  EXPECT_EQ(r.points().size(), 4u);
  expect_tiles_the_face(r);
}

TEST(FaceRefinementTest, points_along_a_chord_in_order_are_joined_one_to_the_next) {
  // A chord from the edge 0-1 to the edge 0-2 with three points inside; then a needle: a chord
  // a hair from corner 0.
  for (const double near0 : {0.5, 1e-6}) {
    SCOPED_TRACE(near0);
    FaceRefinement r(kFace);
    const glm::dvec3 a(1.0 - near0, near0, 0.0), b(1.0 - near0, 0.0, near0);  // chord ends
    std::vector<int> ids;
    for (int i = 0; i <= 4; ++i) {
      const double s = i / 4.0;
      const VertexId v(static_cast<std::uint32_t>(30 + i));
      ASSERT_EQ(r.insert(v, glm::mix(a, b, s)), v);
      ids.push_back(static_cast<int>(r.points().size()) - 1);
    }
    for (std::size_t i = 0; i + 1 < ids.size(); ++i) EXPECT_TRUE(joined(r, ids[i], ids[i + 1])) << i;
    expect_tiles_the_face(r);
  }
}

}  // namespace
}  // namespace deepcut::detail
