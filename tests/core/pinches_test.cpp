// SPDX-License-Identifier: MIT
// split_pinched_vertices (ops/common/pinches.h) on bow ties: a vertex where fans of faces meet
// only at that point gets one copy per fan beyond the first, and each fan's faces all use one
// vertex; any_pinched tells the same cases apart without editing. Fans of up to 16 faces in all are found by comparing every pair of faces, wider ones by
// sorting their other corners: both ways are run here.
#include "ops/common/pinches.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "deepcut/core/mesh_editor.h"

namespace deepcut::detail {
namespace {

using deepcut::MeshEditor;

// One fan of `faces` triangles around `centre`, its rim on an arc on the side `side` (+1 or -1)
// of the y axis; `degenerate_at` (when below `faces`) adds the face (centre, u, u) after
// triangle `degenerate_at`, u its shared rim vertex.
std::vector<FaceId> add_fan(SurfaceMesh& mesh, VertexId centre, int faces, float side,
                            int degenerate_at = -1) {
  std::vector<VertexId> rim;
  for (int i = 0; i <= faces; ++i) {
    const float a = -1.2f + 2.4f * static_cast<float>(i) / static_cast<float>(faces);
    rim.push_back(mesh.add_vertex({side * std::cos(a), std::sin(a), 0.0f}));
  }
  std::vector<FaceId> out;
  for (int i = 0; i < faces; ++i) {
    out.push_back(side > 0 ? mesh.add_face(centre, rim[i], rim[i + 1])
                           : mesh.add_face(centre, rim[i + 1], rim[i]));
    if (i == degenerate_at) out.push_back(mesh.add_face(centre, rim[i + 1], rim[i + 1]));
  }
  return out;
}

// Splits `centre`, whose faces are the two fans `left` (the lower ids) and `right`: one copy;
// the left fan keeps `centre`, every face of the right fan is re-added on the copy.
void expect_split_in_two(SurfaceMesh& mesh, VertexId centre, const std::vector<FaceId>& left,
                         const std::vector<FaceId>& right) {
  std::vector<FaceId> incident = left;
  incident.insert(incident.end(), right.begin(), right.end());
  const std::size_t vertices = mesh.vertex_count(), faces = mesh.face_count();
  EXPECT_TRUE(any_pinched(mesh, {centre}, incident));  // found without splitting
  EXPECT_EQ(mesh.vertex_count(), vertices);
  EXPECT_EQ(mesh.face_count(), faces);
  MeshEditor editor(mesh);
  const PinchSplits splits = split_pinched_vertices(editor, {centre}, incident);
  ASSERT_EQ(splits.copies.size(), 1u);
  EXPECT_EQ(splits.copies[0].first, centre);
  const VertexId copy = splits.copies[0].second;
  EXPECT_NE(copy, centre);
  auto uses = [&](FaceId f, VertexId v) {
    const Triangle& t = mesh.face(f);
    return t[0] == v || t[1] == v || t[2] == v;
  };
  for (const FaceId f : left) {
    ASSERT_FALSE(mesh.is_deleted(f));
    EXPECT_TRUE(uses(f, centre));
    EXPECT_FALSE(uses(f, copy));
  }
  ASSERT_EQ(splits.replaced.size(), right.size());
  std::set<FaceId> moved;
  for (const auto& [old_face, new_face] : splits.replaced) {
    moved.insert(old_face);
    EXPECT_TRUE(mesh.is_deleted(old_face));
    ASSERT_FALSE(mesh.is_deleted(new_face));
    EXPECT_TRUE(uses(new_face, copy));
    EXPECT_FALSE(uses(new_face, centre));
  }
  EXPECT_EQ(moved, std::set<FaceId>(right.begin(), right.end()));
  EXPECT_EQ(splits.around.size(), left.size() + right.size());
}

TEST(SplitPinchedVertices, SplitsABowTieOfTwoSmallFans) {  // 6 faces: compared pairwise
  SurfaceMesh mesh;
  const VertexId centre = mesh.add_vertex({0, 0, 0});
  const auto left = add_fan(mesh, centre, 3, -1.0f);
  const auto right = add_fan(mesh, centre, 3, 1.0f);
  expect_split_in_two(mesh, centre, left, right);
}

TEST(SplitPinchedVertices, SplitsABowTieOfTwoWideFans) {  // 20 faces: sorted by other corner
  SurfaceMesh mesh;
  const VertexId centre = mesh.add_vertex({0, 0, 0});
  const auto left = add_fan(mesh, centre, 10, -1.0f);
  const auto right = add_fan(mesh, centre, 10, 1.0f);
  expect_split_in_two(mesh, centre, left, right);
}

TEST(SplitPinchedVertices, KeepsADegenerateFaceInItsFan) {
  SurfaceMesh mesh;
  const VertexId centre = mesh.add_vertex({0, 0, 0});
  const auto left = add_fan(mesh, centre, 3, -1.0f);
  const auto right = add_fan(mesh, centre, 3, 1.0f, 1);  // (centre, u, u) between its 2nd and 3rd
  ASSERT_EQ(right.size(), 4u);
  expect_split_in_two(mesh, centre, left, right);
}

TEST(SplitPinchedVertices, LeavesASingleFanAlone) {
  SurfaceMesh mesh;
  const VertexId centre = mesh.add_vertex({0, 0, 0});
  const auto fan = add_fan(mesh, centre, 5, 1.0f);
  EXPECT_FALSE(any_pinched(mesh, {centre}, fan));
  MeshEditor editor(mesh);
  const PinchSplits splits = split_pinched_vertices(editor, {centre}, fan);
  EXPECT_TRUE(splits.copies.empty());
  EXPECT_TRUE(splits.replaced.empty());
}

}  // namespace
}  // namespace deepcut::detail
