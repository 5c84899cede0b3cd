// SPDX-License-Identifier: MIT
// The posed overlay the conforming insertions share (ops/common): input, added and moved
// vertices, in the precision the operation computes in.
#include "ops/common/posed_overlay.h"

#include <gtest/gtest.h>

namespace deepcut::detail {
namespace {

const std::vector<glm::vec3> kInput = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

TEST(PosedOverlay, ReadsTheInputUntilVerticesAreAdded) {
  const PosedOverlay<glm::vec3> posed(kInput);
  EXPECT_EQ(posed.first_new(), 3u);
  EXPECT_EQ(posed(VertexId(1)), glm::vec3(1, 0, 0));
  EXPECT_EQ(posed(2u), glm::vec3(0, 1, 0));
  EXPECT_TRUE(posed.added().empty());
  EXPECT_EQ(&posed.input(), &kInput);
}

TEST(PosedOverlay, AddedVerticesFollowTheInput) {
  PosedOverlay<glm::vec3> posed(kInput);
  posed.add({0.5f, 0, 0});
  posed.add({0, 0.5f, 0});
  EXPECT_EQ(posed(VertexId(3)), glm::vec3(0.5f, 0, 0));
  EXPECT_EQ(posed(VertexId(4)), glm::vec3(0, 0.5f, 0));
  posed.set_added(VertexId(6), {2, 2, 2});  // out of order: the slot between waits
  ASSERT_EQ(posed.added().size(), 4u);
  EXPECT_EQ(posed(VertexId(6)), glm::vec3(2, 2, 2));
  posed.set_added(VertexId(5), {3, 3, 3});
  EXPECT_EQ(posed(VertexId(5)), glm::vec3(3, 3, 3));
  EXPECT_EQ(posed(VertexId(0)), glm::vec3(0, 0, 0));
}

TEST(PosedOverlay, MovedInputVerticesReadTheirNewPosition) {
  PosedOverlay<glm::dvec3> posed(kInput);
  posed.move(VertexId(2), {0, 2, 0});
  posed.move(VertexId(0), {-1, 0, 0});
  posed.move(VertexId(2), {0, 3, 0});  // moved again: the last position counts
  EXPECT_EQ(posed(VertexId(0)), glm::dvec3(-1, 0, 0));
  EXPECT_EQ(posed(VertexId(1)), glm::dvec3(1, 0, 0));
  EXPECT_EQ(posed(VertexId(2)), glm::dvec3(0, 3, 0));
  ASSERT_EQ(posed.moved().size(), 2u);
  EXPECT_EQ(posed.moved()[0].first, 0u);  // by vertex id
  EXPECT_EQ(posed.moved()[1].first, 2u);
  EXPECT_EQ(posed.input()[2], glm::vec3(0, 1, 0));  // the input stays as it was
}

// The drill computes in double: the input's floats are widened exactly, added points keep
// their double precision.
TEST(PosedOverlay, DoublePrecisionKeepsAddedPointsExactly) {
  PosedOverlay<glm::dvec3> posed(kInput);
  const glm::dvec3 p(1.0 / 3.0, 0.1, 0.0);
  posed.add(p);
  EXPECT_EQ(posed(VertexId(3)), p);
  EXPECT_EQ(posed(VertexId(1)), glm::dvec3(1.0, 0.0, 0.0));
}

}  // namespace
}  // namespace deepcut::detail
