// SPDX-License-Identifier: MIT
#include "deepcut/core/mesh_editor.h"

#include <gtest/gtest.h>

#include "fixtures.h"

namespace deepcut {
namespace {

// A two-triangle strip whose vertices carry the given influences.
SurfaceMesh skinned_pair(const std::array<glm::u16vec4, 4>& joints, const std::array<glm::vec4, 4>& weights) {
  SurfaceMesh mesh;
  auto& j = mesh.vertex_attrs().add<glm::u16vec4>(attr::kJoints0);
  auto& w = mesh.vertex_attrs().add<glm::vec4>(attr::kWeights0);
  const glm::vec3 p[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (int i = 0; i < 4; ++i) {
    mesh.add_vertex(p[i]);
    j[std::size_t(i)] = joints[std::size_t(i)];
    w[std::size_t(i)] = weights[std::size_t(i)];
  }
  mesh.add_face(VertexId(0), VertexId(1), VertexId(2));
  mesh.add_face(VertexId(0), VertexId(2), VertexId(3));
  return mesh;
}

float weight_of(const SurfaceMesh& mesh, VertexId v, int joint) {
  const auto& j = mesh.vertex_attrs().get<glm::u16vec4>(attr::kJoints0)[v.index];
  const auto& w = mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0)[v.index];
  float sum = 0.0f;
  for (int c = 0; c < 4; ++c)
    if (j[c] == joint) sum += w[c];
  return sum;
}

}  // namespace

TEST(MeshEditorTest, edge_split_blends_union_of_joints) {
  SurfaceMesh mesh = skinned_pair({glm::u16vec4{1, 0, 0, 0}, {2, 3, 0, 0}, {1, 0, 0, 0}, {1, 0, 0, 0}},
                                  {glm::vec4{1, 0, 0, 0}, {0.6f, 0.4f, 0, 0}, {1, 0, 0, 0}, {1, 0, 0, 0}});
  MeshEditor editor(mesh);
  const VertexId v = editor.add_vertex_on_edge(VertexId(0), VertexId(1), 0.5f);
  EXPECT_EQ(mesh.position(v), glm::vec3(0.5f, 0, 0));
  EXPECT_NEAR(weight_of(mesh, v, 1), 0.5f, 1e-6);
  EXPECT_NEAR(weight_of(mesh, v, 2), 0.3f, 1e-6);
  EXPECT_NEAR(weight_of(mesh, v, 3), 0.2f, 1e-6);
  const auto& j = mesh.vertex_attrs().get<glm::u16vec4>(attr::kJoints0)[v.index];
  const auto& w = mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0)[v.index];
  EXPECT_EQ(j[3], 0);  // unused slot: joint 0, weight 0
  EXPECT_EQ(w[3], 0.0f);
  ASSERT_EQ(editor.log().size(), 1u);
  EXPECT_TRUE(std::holds_alternative<VertexAdded>(editor.log().edits[0]));
}

TEST(MeshEditorTest, more_than_four_influences_keep_the_largest_four_renormalised) {
  SurfaceMesh mesh = skinned_pair({glm::u16vec4{1, 2, 3, 0}, {4, 5, 6, 0}, {1, 0, 0, 0}, {1, 0, 0, 0}},
                                  {glm::vec4{0.5f, 0.3f, 0.2f, 0}, {0.45f, 0.35f, 0.2f, 0}, {1, 0, 0, 0}, {1, 0, 0, 0}});
  MeshEditor editor(mesh);
  const VertexId v = editor.add_vertex_on_edge(VertexId(0), VertexId(1), 0.5f);
  // Blended: 1:.25 2:.15 3:.1 4:.225 5:.175 6:.1 -> keep 1, 4, 5, 2 (sum .8).
  EXPECT_NEAR(weight_of(mesh, v, 1), 0.25f / 0.8f, 1e-6);
  EXPECT_NEAR(weight_of(mesh, v, 4), 0.225f / 0.8f, 1e-6);
  EXPECT_NEAR(weight_of(mesh, v, 5), 0.175f / 0.8f, 1e-6);
  EXPECT_NEAR(weight_of(mesh, v, 2), 0.15f / 0.8f, 1e-6);
  EXPECT_EQ(weight_of(mesh, v, 3), 0.0f);
  EXPECT_EQ(weight_of(mesh, v, 6), 0.0f);
  test::expect_valid(mesh, 7);
}

TEST(MeshEditorTest, face_split_interpolates_corner_uvs_in_the_parent_and_keeps_seams) {
  SurfaceMesh mesh = test::make_grid(2, 1);  // the seam runs down x = 0.5
  MeshEditor editor(mesh);
  const FaceId parent(2);  // right of the seam: u = x + 1
  const Triangle t = mesh.face(parent);
  const glm::vec3 bary(0.2f, 0.3f, 0.5f);
  const VertexId c = editor.add_vertex_in_triangle(t, bary);
  const glm::vec3 expected = bary.x * mesh.position(t[0]) + bary.y * mesh.position(t[1]) + bary.z * mesh.position(t[2]);
  EXPECT_NEAR(glm::length(mesh.position(c) - expected), 0.0f, 1e-6f);
  editor.remove_face(parent);
  const FaceId f = editor.add_face_from({t[0], t[1], c}, parent, {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), bary});
  const auto& uv = mesh.corner_attrs().get<glm::vec2>(attr::kUv0);
  EXPECT_NEAR(uv[SurfaceMesh::corner(f, 2)].x, expected.x + 1.0f, 1e-6f);
  EXPECT_NEAR(uv[SurfaceMesh::corner(f, 2)].y, expected.y, 1e-6f);
  EXPECT_EQ(uv[SurfaceMesh::corner(f, 0)], uv[SurfaceMesh::corner(parent, 0)]);
  const auto& n = mesh.corner_attrs().get<glm::vec3>(attr::kNormal);
  EXPECT_NEAR(glm::length(n[SurfaceMesh::corner(f, 2)]), 1.0f, 1e-6f);
  EXPECT_EQ(editor.log().size(), 3u);
  EXPECT_THROW(editor.remove_face(parent), Error);
}

TEST(MeshEditorTest, normalize_influences_handles_zero_nan_and_duplicates) {
  std::uint16_t j[4] = {3, 3, 5, 7};
  float w[4] = {0.2f, 0.2f, std::nanf(""), -1.0f};
  EXPECT_TRUE(normalize_influences(j, w, 4));
  EXPECT_FLOAT_EQ(w[0], 1.0f);
  EXPECT_EQ(j[1], 0);
  EXPECT_EQ(w[2], 0.0f);
  std::uint16_t z[4] = {4, 0, 0, 0};
  float zw[4] = {0, 0, 0, 0};
  EXPECT_FALSE(normalize_influences(z, zw, 4));
  EXPECT_EQ(z[0], 4);
  EXPECT_EQ(zw[0], 1.0f);
}

}  // namespace deepcut
