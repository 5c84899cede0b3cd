// SPDX-License-Identifier: MIT
// The posed overlay the conforming insertions share (ops/common): input, added and moved
// vertices, in the precision the operation computes in; and the placement that puts new
// vertices at their posed points in bind space.
#include "ops/common/posed_overlay.h"

#include <gtest/gtest.h>

#include "deepcut/core/skinning.h"
#include "fixtures.h"
#include "ops/common/placement.h"

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

// The filter over moved vertices keeps one bit per vertex modulo 1024: vertices sharing a bit
// with a moved one still read the input, and more moved vertices than bits all read back.
TEST(PosedOverlay, MovedVerticesSharingTheFilterReadCorrectly) {
  std::vector<glm::vec3> input(4096);
  for (std::size_t i = 0; i < input.size(); ++i) input[i] = glm::vec3(static_cast<float>(i), 0, 0);
  PosedOverlay<glm::dvec3> posed(input);
  posed.move(VertexId(3), {-3, 1, 0});
  EXPECT_EQ(posed(VertexId(3 + 1024)), glm::dvec3(3 + 1024, 0, 0));
  EXPECT_FALSE(posed.is_moved(VertexId(3 + 1024)));
  EXPECT_TRUE(posed.is_moved(VertexId(3)));
  posed.move(VertexId(1027), {-1027, 1, 0});
  EXPECT_EQ(posed(VertexId(1027 + 1024)), glm::dvec3(1027 + 1024, 0, 0));
  EXPECT_FALSE(posed.is_moved(VertexId(1027 + 1024)));
  EXPECT_EQ(posed(VertexId(1027)), glm::dvec3(-1027, 1, 0));
  EXPECT_EQ(posed(VertexId(3)), glm::dvec3(-3, 1, 0));

  PosedOverlay<glm::dvec3> many(input);
  for (std::uint32_t v = 0; v < 3000; v += 2) many.move(VertexId(v), {-double(v), 1, 0});  // 1500 moved
  for (std::uint32_t v = 0; v < input.size(); ++v) {
    const bool moved = v < 3000 && v % 2 == 0;
    EXPECT_EQ(many.is_moved(VertexId(v)), moved) << v;
    EXPECT_EQ(many(VertexId(v)), moved ? glm::dvec3(-double(v), 1, 0) : glm::dvec3(v, 0, 0)) << v;
  }
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

// The skinned tube bent 60 degrees (t = 1 of its clip) and a vertex made between two vertices
// of different weights: where its blended skin poses its interpolated bind position, and where
// it should be.
struct BentTube {
  Model model = test::make_skinned_tube_model();
  PosedModel posed;
  SurfaceMesh mesh;
  explicit BentTube(int animation)
      : posed(PosedModel::build(model, animation, 1.0f)), mesh(model.meshes[0].primitives[0].mesh) {}
  const PosedMesh& inst() const { return *posed.find(0, 0); }
  glm::vec3 pose_of(VertexId v) const {
    return glm::vec3(SkinBlend(mesh, inst().joints).matrix(v.index) * glm::vec4(mesh.position(v), 1.0f));
  }
};

TEST(Placement, ANewVertexOfABentSkinPosesAtItsTarget) {
  BentTube tube(0);
  MeshEditor editor(tube.mesh);
  const detail::Placement placement(tube.inst(), tube.mesh);
  ASSERT_TRUE(placement.unposes());
  const VertexId a(2 * 16 + 3), b(7 * 16 + 5);
  const VertexId v = editor.add_vertex_on_edge(a, b, 0.3f);
  const glm::vec3 target = glm::mix(tube.inst().posed[a.index], tube.inst().posed[b.index], 0.3f);
  EXPECT_GT(glm::length(tube.pose_of(v) - target), 1e-2f)
      << "interpolated in bind space, it poses beside the target";
  placement.place(editor, v, target);
  EXPECT_LT(glm::length(tube.pose_of(v) - target), 1e-5f);
  EXPECT_EQ(glm::length(editor.mesh().position(v) - placement.bind_position(tube.mesh, v, target, {})), 0.0f);
}

TEST(Placement, AtRestTheInterpolatedBindPositionIsKeptBitForBit) {
  BentTube tube(-1);
  MeshEditor editor(tube.mesh);
  const detail::Placement placement(tube.inst(), tube.mesh);
  const VertexId a(2 * 16 + 3), b(7 * 16 + 5);
  const VertexId v = editor.add_vertex_on_edge(a, b, 0.3f);
  const glm::vec3 interpolated = tube.mesh.position(v);
  placement.place(editor, v, glm::mix(tube.inst().posed[a.index], tube.inst().posed[b.index], 0.3f));
  EXPECT_EQ(tube.mesh.position(v), interpolated);
  EXPECT_EQ(editor.log().size(), 1u) << "no VertexMoved";
}

TEST(Placement, AMeshPosedAtGivenPositionsIsNotUnposed) {
  SurfaceMesh mesh = test::make_grid(3, 3);
  const PosedMesh at = PosedMesh::at_positions(mesh);
  const detail::Placement placement(at, mesh);
  EXPECT_FALSE(placement.unposes());
  EXPECT_EQ(placement.bind_position(mesh, VertexId(0), {5, 5, 5}, {1, 2, 3}), glm::vec3(1, 2, 3));
}

}  // namespace
}  // namespace deepcut::detail
