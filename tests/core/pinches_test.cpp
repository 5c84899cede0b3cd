// SPDX-License-Identifier: MIT
// split_pinched_vertices (ops/common/pinches.h) on bow ties: a vertex where fans of faces meet
// only at that point gets one copy per fan beyond the first, and each fan's faces all use one
// vertex; any_pinched tells the same cases apart without editing. Up to 16 faces around a vertex,
// each using it once, are grouped by comparing pairs; wider lists, or a face using the vertex at
// two corners, by sorting their other corners: both ways are run here.
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

// any_pinched on `candidates` says what split_pinched_vertices does (on a copy of `mesh`): true
// exactly when it makes copies, and it makes `copies` of them.
void expect_agree(const SurfaceMesh& mesh, const std::vector<VertexId>& candidates,
                  const std::vector<FaceId>& incident, std::size_t copies) {
  const bool pinched = any_pinched(mesh, candidates, incident);
  SurfaceMesh split = mesh;
  MeshEditor editor(split);
  const PinchSplits splits = split_pinched_vertices(editor, candidates, incident);
  EXPECT_EQ(pinched, !splits.copies.empty());
  EXPECT_EQ(splits.copies.size(), copies);
}

std::vector<FaceId> joined(std::vector<FaceId> a, const std::vector<FaceId>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

TEST(AnyPinched, AFaceAtTwoCornersOfTheVertexIsSorted) {  // 7 faces, one using the centre twice
  SurfaceMesh mesh;
  const VertexId centre = mesh.add_vertex({0, 0, 0});
  const auto left = add_fan(mesh, centre, 3, -1.0f);
  auto right = add_fan(mesh, centre, 3, 1.0f);
  const VertexId u = mesh.face(right[1])[1];
  right.push_back(mesh.add_face(centre, centre, u));
  expect_agree(mesh, {centre}, joined(left, right), 1);
  expect_agree(mesh, {centre}, right, 0);
}

TEST(AnyPinched, FansOfSixteenAndSeventeenFaces) {  // the last pairwise size and the first sorted
  for (const int faces : {16, 17}) {
    SCOPED_TRACE(testing::Message() << faces << " faces");
    SurfaceMesh mesh;
    const VertexId centre = mesh.add_vertex({0, 0, 0});
    const auto left = add_fan(mesh, centre, 8, -1.0f);
    const auto right = add_fan(mesh, centre, faces - 8, 1.0f);
    expect_agree(mesh, {centre}, joined(left, right), 1);
    SurfaceMesh one;
    const VertexId c1 = one.add_vertex({0, 0, 0});
    expect_agree(one, {c1}, add_fan(one, c1, faces, 1.0f), 0);
  }
  SurfaceMesh wide;  // a single fan wider than 16
  const VertexId c = wide.add_vertex({0, 0, 0});
  expect_agree(wide, {c}, add_fan(wide, c, 20, 1.0f), 0);
}

TEST(AnyPinched, ThreeFansGetTwoCopies) {
  SurfaceMesh mesh;
  const VertexId centre = mesh.add_vertex({0, 0, 0});
  const auto a = add_fan(mesh, centre, 3, -1.0f), b = add_fan(mesh, centre, 3, 1.0f);
  const auto c = add_fan(mesh, centre, 2, 1.0f);
  expect_agree(mesh, {centre}, joined(joined(a, b), c), 2);
}

// Face 0 (r0, r1) and face 1 (r2, r3) join only through face 2 (r1, r2), found after them.
TEST(AnyPinched, AFanJoinedThroughALaterFace) {
  for (const bool bow_tie : {false, true}) {
    SCOPED_TRACE(bow_tie ? "with a second fan" : "one fan");
    SurfaceMesh mesh;
    const VertexId centre = mesh.add_vertex({0, 0, 0});
    VertexId r[4];
    for (int i = 0; i < 4; ++i) r[i] = mesh.add_vertex({std::cos(0.5f * i), std::sin(0.5f * i), 0});
    std::vector<FaceId> fan = {mesh.add_face(centre, r[0], r[1]), mesh.add_face(centre, r[2], r[3]),
                               mesh.add_face(centre, r[1], r[2])};
    if (bow_tie) fan = joined(fan, add_fan(mesh, centre, 3, -1.0f));
    expect_agree(mesh, {centre}, fan, bow_tie ? 1 : 0);
  }
}

TEST(AnyPinched, OnlyTheLastCandidateIsPinched) {
  SurfaceMesh mesh;
  const VertexId a = mesh.add_vertex({0, 0, 0}), b = mesh.add_vertex({0, 0, 1}),
                 c = mesh.add_vertex({0, 0, 2});
  auto incident = joined(add_fan(mesh, a, 4, 1.0f), add_fan(mesh, b, 5, -1.0f));
  incident = joined(incident, joined(add_fan(mesh, c, 3, -1.0f), add_fan(mesh, c, 3, 1.0f)));
  expect_agree(mesh, {a, b, c}, incident, 1);
}

}  // namespace
}  // namespace deepcut::detail
