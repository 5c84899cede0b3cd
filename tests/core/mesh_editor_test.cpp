// SPDX-License-Identifier: MIT
#include "deepcut/core/mesh_editor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <variant>
#include <vector>

#include "deepcut/core/adjacency.h"
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


// Influences of vertex v over every set the mesh carries, slot order.
std::vector<std::pair<int, float>> influences_of(const SurfaceMesh& mesh, VertexId v) {
  std::vector<std::pair<int, float>> out;
  const char* names[2][2] = {{attr::kJoints0, attr::kWeights0}, {attr::kJoints1, attr::kWeights1}};
  for (const auto& pair : names) {
    const auto* j = mesh.vertex_attrs().find<glm::u16vec4>(pair[0]);
    const auto* w = mesh.vertex_attrs().find<glm::vec4>(pair[1]);
    if (!j || !w) break;
    for (int c = 0; c < 4; ++c) out.emplace_back((*j)[v.index][c], (*w)[v.index][c]);
  }
  return out;
}

// A triangle whose three vertices carry `sets` sets of influences (joints, weights per vertex,
// 4 * sets each).
SurfaceMesh skinned_triangle(int sets, const std::array<std::vector<int>, 3>& joints,
                             const std::array<std::vector<float>, 3>& weights) {
  SurfaceMesh mesh;
  const char* names[2][2] = {{attr::kJoints0, attr::kWeights0}, {attr::kJoints1, attr::kWeights1}};
  const glm::vec3 p[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (int i = 0; i < 3; ++i) mesh.add_vertex(p[i]);
  for (int k = 0; k < sets; ++k) {
    auto& j = mesh.vertex_attrs().add<glm::u16vec4>(names[k][0]);
    auto& w = mesh.vertex_attrs().add<glm::vec4>(names[k][1]);
    for (std::size_t i = 0; i < 3; ++i)
      for (int c = 0; c < 4; ++c) {
        const std::size_t slot = std::size_t(4 * k + c);
        j[i][c] = slot < joints[i].size() ? static_cast<std::uint16_t>(joints[i][slot]) : 0;
        w[i][c] = slot < weights[i].size() ? weights[i][slot] : 0.0f;
      }
  }
  mesh.add_face(VertexId(0), VertexId(1), VertexId(2));
  return mesh;
}

// The rule, computed apart from the editor: the sources' weighted influences merged by joint,
// sorted largest first (first appearance breaks ties), the largest `slots` kept, renormalised.
std::vector<std::pair<int, double>> expected_blend(const SurfaceMesh& mesh, const std::vector<VertexId>& src,
                                                   const std::vector<float>& w, std::size_t slots) {
  std::vector<std::pair<int, double>> merged;
  for (std::size_t s = 0; s < src.size(); ++s)
    for (const auto& [joint, weight] : influences_of(mesh, src[s])) {
      if (weight <= 0.0f || w[s] <= 0.0f) continue;
      auto it = std::find_if(merged.begin(), merged.end(), [&](const auto& m) { return m.first == joint; });
      if (it == merged.end()) it = merged.insert(merged.end(), {joint, 0.0});
      it->second += double(weight) * double(w[s]);
    }
  std::stable_sort(merged.begin(), merged.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  if (merged.size() > slots) merged.resize(slots);
  double sum = 0.0;
  for (const auto& m : merged) sum += m.second;
  for (auto& m : merged) m.second /= sum;
  return merged;
}

// The invariants every new vertex's influences keep: at most `slots`, each set present before
// and no other, largest first, summing to 1, zero slots on joint 0, and equal to the rule.
void expect_influence_rule(const SurfaceMesh& mesh, VertexId v, const std::vector<VertexId>& src,
                           const std::vector<float>& w, std::size_t slots) {
  const auto got = influences_of(mesh, v);
  ASSERT_EQ(got.size(), slots) << "the primitive's sets, no more";
  double sum = 0.0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    sum += got[i].second;
    if (i > 0) {
      EXPECT_GE(got[i - 1].second, got[i].second) << "largest first, slot " << i;
    }
    if (got[i].second == 0.0f) {
      EXPECT_EQ(got[i].first, 0) << "unused slot " << i;
    }
  }
  EXPECT_NEAR(sum, 1.0, 1e-6);
  const auto want = expected_blend(mesh, src, w, slots);
  for (std::size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(got[i].first, want[i].first) << "slot " << i;
    EXPECT_NEAR(got[i].second, want[i].second, 1e-6) << "slot " << i;
  }
  for (std::size_t i = want.size(); i < got.size(); ++i) EXPECT_EQ(got[i].second, 0.0f) << "slot " << i;
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

TEST(MeshEditorTest, a_four_influence_primitive_never_gets_a_fifth) {
  // Two parents with four disjoint joints each: the split sees eight and keeps four.
  SurfaceMesh mesh = skinned_triangle(1, {std::vector<int>{1, 2, 3, 4}, {5, 6, 7, 8}, {9, 10, 11, 12}},
                                      {std::vector<float>{0.4f, 0.3f, 0.2f, 0.1f}, {0.35f, 0.3f, 0.25f, 0.1f},
                                       {0.7f, 0.1f, 0.1f, 0.1f}});
  MeshEditor editor(mesh);
  const VertexId e = editor.add_vertex_on_edge(VertexId(0), VertexId(1), 0.4f);
  EXPECT_EQ(mesh.vertex_attrs().find<glm::u16vec4>(attr::kJoints1), nullptr);
  expect_influence_rule(mesh, e, {VertexId(0), VertexId(1)}, {0.6f, 0.4f}, 4);
  // Twelve joints from a point inside the triangle, and a split of a split.
  const VertexId f = editor.add_vertex_in_triangle(mesh.face(FaceId(0)), glm::vec3(0.3f, 0.3f, 0.4f));
  expect_influence_rule(mesh, f, {VertexId(0), VertexId(1), VertexId(2)}, {0.3f, 0.3f, 0.4f}, 4);
  const VertexId g = editor.add_vertex_on_edge(e, f, 0.5f);
  expect_influence_rule(mesh, g, {e, f}, {0.5f, 0.5f}, 4);
  test::expect_valid(mesh, 13);
}

TEST(MeshEditorTest, an_eight_influence_primitive_keeps_up_to_eight) {
  SurfaceMesh mesh = skinned_triangle(2, {std::vector<int>{1, 2, 3, 4, 5, 6}, {7, 8, 9, 10, 11, 12, 13, 14}, {1, 7}},
                                      {std::vector<float>{0.3f, 0.2f, 0.2f, 0.1f, 0.1f, 0.1f},
                                       {0.2f, 0.2f, 0.1f, 0.1f, 0.1f, 0.1f, 0.1f, 0.1f}, {0.5f, 0.5f}});
  MeshEditor editor(mesh);
  const VertexId e = editor.add_vertex_on_edge(VertexId(0), VertexId(1), 0.5f);  // 14 joints, 8 kept
  expect_influence_rule(mesh, e, {VertexId(0), VertexId(1)}, {0.5f, 0.5f}, 8);
  int used = 0;
  for (const auto& [joint, weight] : influences_of(mesh, e)) used += weight > 0.0f;
  EXPECT_EQ(used, 8);
  const VertexId f = editor.add_vertex_on_edge(VertexId(0), VertexId(2), 0.25f);  // 1 merged: 7 joints, all kept
  expect_influence_rule(mesh, f, {VertexId(0), VertexId(2)}, {0.75f, 0.25f}, 8);
  used = 0;
  for (const auto& [joint, weight] : influences_of(mesh, f)) used += weight > 0.0f;
  EXPECT_EQ(used, 7);
  test::expect_valid(mesh, 15);
}

TEST(MeshEditorTest, influence_ties_keep_the_joints_that_appear_first) {
  // Eight equal blended weights for four slots: the first source's joints, in slot order,
  // whichever way round the edge is split.
  SurfaceMesh mesh = skinned_triangle(1, {std::vector<int>{4, 3, 2, 1}, {8, 7, 6, 5}, {1, 0, 0, 0}},
                                      {std::vector<float>{0.25f, 0.25f, 0.25f, 0.25f}, {0.25f, 0.25f, 0.25f, 0.25f},
                                       {1, 0, 0, 0}});
  MeshEditor editor(mesh);
  const VertexId ab = editor.add_vertex_on_edge(VertexId(0), VertexId(1), 0.5f);
  const VertexId ba = editor.add_vertex_on_edge(VertexId(1), VertexId(0), 0.5f);
  const auto first = influences_of(mesh, ab), second = influences_of(mesh, ba);
  for (int c = 0; c < 4; ++c) {
    EXPECT_EQ(first[std::size_t(c)].first, 4 - c);
    EXPECT_EQ(second[std::size_t(c)].first, 8 - c);
    EXPECT_FLOAT_EQ(first[std::size_t(c)].second, 0.25f);
  }
  expect_influence_rule(mesh, ab, {VertexId(0), VertexId(1)}, {0.5f, 0.5f}, 4);
}

TEST(MeshEditorTest, random_splits_follow_the_influence_rule) {
  std::mt19937 rng(18);
  std::uniform_int_distribution<int> joint(0, 9);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int trial = 0; trial < 200; ++trial) {
    const int sets = 1 + trial % 2;
    std::array<std::vector<int>, 3> joints;
    std::array<std::vector<float>, 3> weights;
    for (std::size_t i = 0; i < 3; ++i) {
      float sum = 0.0f;
      for (int c = 0; c < 4 * sets; ++c) {
        joints[i].push_back(joint(rng));  // repeats on purpose: merged by joint
        weights[i].push_back(unit(rng) < 0.3f ? 0.0f : unit(rng));
        sum += weights[i].back();
      }
      if (sum == 0.0f) weights[i][0] = sum = 1.0f;
      for (float& w : weights[i]) w /= sum;
    }
    SurfaceMesh mesh = skinned_triangle(sets, joints, weights);
    MeshEditor editor(mesh);
    const std::size_t slots = std::size_t(4 * sets);
    const float t = unit(rng);
    const VertexId e = editor.add_vertex_on_edge(VertexId(0), VertexId(1), t);
    expect_influence_rule(mesh, e, {VertexId(0), VertexId(1)}, {1.0f - t, t}, slots);
    glm::vec3 bary(unit(rng) + 0.01f, unit(rng) + 0.01f, unit(rng) + 0.01f);
    bary /= bary.x + bary.y + bary.z;
    const VertexId f = editor.add_vertex_in_triangle(mesh.face(FaceId(0)), bary);
    expect_influence_rule(mesh, f, {VertexId(0), VertexId(1), VertexId(2)}, {bary.x, bary.y, bary.z}, slots);
    if (HasFailure()) break;
  }
}

TEST(MeshEditorTest, blend_influences_refuses_counts_it_has_no_room_for) {
  const std::uint16_t joints[4 * kMaxInfluences] = {};
  const float weights[4 * kMaxInfluences] = {1.0f};
  const float w[4] = {1, 0, 0, 0};
  std::uint16_t out_joints[kMaxInfluences];
  float out_weights[kMaxInfluences];
  EXPECT_THROW(blend_influences(joints, weights, w, 4, 4, out_joints, out_weights), Error);
  EXPECT_THROW(blend_influences(joints, weights, w, 1, 12, out_joints, out_weights), Error);
  EXPECT_THROW(blend_influences(joints, weights, w, 0, 4, out_joints, out_weights), Error);
  blend_influences(joints, weights, w, 1, 4, out_joints, out_weights);
  EXPECT_EQ(out_weights[0], 1.0f);
}

// A new vertex blends one to kMaxBlendSources sources, the slots of its log entry (the editor's
// blend takes the count as a constant and refuses more when compiled): an edge split fills two
// slots and leaves the third empty, a point in a triangle fills all three, in the callers' order.
TEST(MeshEditorTest, a_new_vertex_logs_its_sources_in_the_entry_slots) {
  static_assert(std::tuple_size<decltype(VertexAdded::from)>::value == kMaxBlendSources, "one slot a source");
  SurfaceMesh mesh = skinned_pair({glm::u16vec4{1, 0, 0, 0}, {2, 0, 0, 0}, {3, 0, 0, 0}, {1, 0, 0, 0}},
                                  {glm::vec4{1, 0, 0, 0}, {1, 0, 0, 0}, {1, 0, 0, 0}, {1, 0, 0, 0}});
  MeshEditor editor(mesh);
  const VertexId e = editor.add_vertex_on_edge(VertexId(1), VertexId(0), 0.25f);
  const VertexId p =
      editor.add_vertex_in_triangle({VertexId(2), VertexId(0), VertexId(1)}, {0.5f, 0.3f, 0.2f});
  ASSERT_EQ(editor.log().size(), 2u);
  const auto& on_edge = std::get<VertexAdded>(editor.log().edits[0]);
  EXPECT_EQ(on_edge.v, e);
  EXPECT_EQ(on_edge.from, (std::array<VertexId, 3>{VertexId(1), VertexId(0), VertexId()}));
  EXPECT_EQ(on_edge.weight, (std::array<float, 3>{0.75f, 0.25f, 0.0f}));
  const auto& in_triangle = std::get<VertexAdded>(editor.log().edits[1]);
  EXPECT_EQ(in_triangle.v, p);
  EXPECT_EQ(in_triangle.from, (std::array<VertexId, 3>{VertexId(2), VertexId(0), VertexId(1)}));
  EXPECT_EQ(in_triangle.weight, (std::array<float, 3>{0.5f, 0.3f, 0.2f}));
  // Each blended its own sources' skin: joint 1 at 0.25 on the edge, joints 3, 1, 2 in the triangle.
  EXPECT_NEAR(weight_of(mesh, e, 1), 0.25f, 1e-6);
  EXPECT_NEAR(weight_of(mesh, e, 2), 0.75f, 1e-6);
  EXPECT_NEAR(weight_of(mesh, p, 3), 0.5f, 1e-6);
  EXPECT_NEAR(weight_of(mesh, p, 1), 0.3f, 1e-6);
  EXPECT_NEAR(weight_of(mesh, p, 2), 0.2f, 1e-6);
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

namespace {

// Bytes of every face slot, deletion flag and attribute of `mesh`, for exact comparison.
std::vector<unsigned char> mesh_bytes(const SurfaceMesh& mesh) {
  std::vector<unsigned char> out;
  auto put = [&](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    out.insert(out.end(), b, b + n);
  };
  put(mesh.faces().data(), mesh.faces().size() * sizeof(Triangle));
  for (std::uint32_t f = 0; f < mesh.face_slots(); ++f) out.push_back(mesh.is_deleted(FaceId(f)) ? 1 : 0);
  for (const AttributeSet* set : {&mesh.vertex_attrs(), &mesh.face_attrs(), &mesh.corner_attrs()})
    for (const std::string& name : set->names()) {
      const AttributeArrayBase& a = *set->base(name);
      for (std::size_t i = 0; i < a.size(); ++i) put(a.element_data(i), a.element_bytes());
    }
  return out;
}

}  // namespace

TEST(MeshEditorTest, a_face_batch_equals_its_calls_one_after_another) {
  // The same mesh and the same log, in the same order, as removing and adding face by face.
  SurfaceMesh start = test::make_grid(3, 2);
  start.corner_attrs().add<glm::vec4>(attr::kTangent, glm::vec4(1.0f, 0.0f, 0.0f, -1.0f));
  start.face_attrs().add<std::uint8_t>(attr::kCutSurface);
  start.face_attrs().get<std::uint8_t>(attr::kCutSurface)[3] = 1;
  start.corner_attrs().get<glm::vec3>(attr::kNormal)[4] = glm::vec3(-0.0f, 2.0f, 0.0f);
  SurfaceMesh one = start, batched = start;
  MeshEditor by_call(one), by_batch(batched);
  FaceBatch batch;
  const std::array<glm::vec3, 3> halves = {glm::vec3(1, 0, 0), glm::vec3(0, 0.5f, 0.5f), glm::vec3(0, 0, 1)};
  const std::array<glm::vec3, 3> same = {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)};
  for (std::uint32_t f : {1u, 4u, 3u}) {
    const Triangle t = start.face(FaceId(f));
    by_call.remove_face(FaceId(f));
    batch.remove(FaceId(f));
    for (const Triangle& made : {Triangle{t[0], t[1], t[2]}, Triangle{t[2], t[0], t[1]}}) {
      by_call.add_face_from(made, FaceId(f), f == 3 ? same : halves);
      batch.add_from(made, FaceId(f), f == 3 ? same : halves);
    }
  }
  batch.remove(FaceId(0));
  by_call.remove_face(FaceId(0));
  by_batch.apply(batch);
  EXPECT_TRUE(batch.empty());
  EXPECT_EQ(mesh_bytes(batched), mesh_bytes(one));
  ASSERT_EQ(by_batch.log().size(), by_call.log().size());
  for (std::size_t i = 0; i < by_call.log().size(); ++i) {
    const Edit& a = by_batch.log().edits[i];
    const Edit& b = by_call.log().edits[i];
    ASSERT_EQ(a.index(), b.index()) << i;
    if (const auto* x = std::get_if<FaceAdded>(&a)) {
      const auto& y = std::get<FaceAdded>(b);
      EXPECT_TRUE(x->f == y.f && x->parent == y.parent && x->vertices == y.vertices) << i;
    } else {
      const auto& x2 = std::get<FaceRemoved>(a);
      const auto& y2 = std::get<FaceRemoved>(b);
      EXPECT_TRUE(x2.f == y2.f && x2.vertices == y2.vertices) << i;
    }
  }
  // A vertex out of range or a face not live: refused before any change.
  const std::vector<unsigned char> before = mesh_bytes(batched);
  batch.remove(FaceId(5));
  batch.add_from({VertexId(0), VertexId(1), VertexId(999)}, FaceId(5), same);
  EXPECT_THROW(by_batch.apply(batch), Error);
  FaceBatch dead;
  dead.remove(FaceId(1));
  EXPECT_THROW(by_batch.apply(dead), Error);
  EXPECT_EQ(mesh_bytes(batched), before);
}

TEST(MeshEditorTest, a_face_batch_normalises_corner_directions_as_face_by_face) {
  // A batch normalises its corners' normals and tangents four at a time, a face made alone its
  // three one by one: the same bits, for lengths of every kind (zero, -0, tiny, huge, infinite,
  // NaN where an infinite component meets a zero weight) and handedness from the dominant parent
  // corner of either sign (ties: the first). No NaN goes in: the batch's blend may add two NaNs
  // in another order than a face's, which can change a NaN's sign before any normalising.
  SurfaceMesh start = test::make_grid(4, 4);
  start.corner_attrs().add<glm::vec4>(attr::kTangent);
  auto& normals = start.corner_attrs().get<glm::vec3>(attr::kNormal);
  auto& tangents = start.corner_attrs().get<glm::vec4>(attr::kTangent);
  std::mt19937 rng(19);
  const float odd[] = {0.0f, -0.0f, 1e-44f, -3e-39f, 1e30f, -7.5f, INFINITY, -INFINITY};
  auto pick = [&] {
    return rng() % 2 ? std::uniform_real_distribution<float>(-2.0f, 2.0f)(rng) : odd[rng() % 8];
  };
  for (std::size_t c = 0; c < normals.size(); ++c) {
    normals[c] = glm::vec3(pick(), pick(), pick());
    tangents[c] = glm::vec4(pick(), pick(), pick(), pick());
  }
  for (std::size_t c = 0; c < 6; ++c) normals[c] = glm::vec3(0.6f, -0.8f, 0.0f) * float(c);  // plain ones too
  SurfaceMesh one = start, batched = start;
  MeshEditor by_call(one), by_batch(batched);
  FaceBatch batch;
  for (std::uint32_t f = 0; f < start.face_slots(); ++f) {
    std::array<glm::vec3, 3> bary;
    for (auto& b : bary) {
      const float x = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
      b = rng() % 4 == 0 ? glm::vec3(0.5f, 0.5f, 0.0f) : glm::vec3(x, (1.0f - x) * 0.5f, (1.0f - x) * 0.5f);
    }
    const Triangle t = start.face(FaceId(f));
    by_call.add_face_from(t, FaceId(f), bary);
    batch.add_from(t, FaceId(f), bary);
  }
  by_batch.apply(batch);
  EXPECT_EQ(mesh_bytes(batched), mesh_bytes(one));
}

TEST(MeshEditorTest, a_vertex_batch_equals_its_calls_one_after_another) {
  // The same mesh and the same log as adding vertex by vertex: more vertices than one run, some
  // on edges to vertices the batch made before them; then faces on them, and the adjacency
  // following the log matches a rebuild.
  const SurfaceMesh start = test::make_grid(6, 5);
  const auto nv = static_cast<std::uint32_t>(start.vertex_count());
  std::mt19937 rng(7);
  std::vector<std::uint32_t> ends;
  std::vector<float> t;
  for (std::uint32_t i = 0; i < 150; ++i) {
    const std::uint32_t a = rng() % (nv + i), b = (a + 1 + rng() % (nv + i - 1)) % (nv + i);
    ends.insert(ends.end(), {a, b});
    t.push_back(std::uniform_real_distribution<float>(0.0f, 1.0f)(rng));
  }
  t[3] = 0.0f;  // a copy of its first end
  SurfaceMesh one = start, batched = start;
  MeshEditor by_call(one), by_batch(batched);
  for (std::size_t i = 0; i < t.size(); ++i)
    by_call.add_vertex_on_edge(VertexId(ends[2 * i]), VertexId(ends[2 * i + 1]), t[i]);
  EXPECT_EQ(by_batch.add_vertices_on_edges(ends.data(), t.data(), t.size()), VertexId(nv));
  EXPECT_EQ(mesh_bytes(batched), mesh_bytes(one));
  ASSERT_EQ(by_batch.log().size(), by_call.log().size());
  for (std::size_t i = 0; i < by_call.log().size(); ++i) {
    const auto& x = std::get<VertexAdded>(by_batch.log().edits[i]);
    const auto& y = std::get<VertexAdded>(by_call.log().edits[i]);
    // memcmp: -0.0 and +0.0 weights are told apart.
    const bool same_weights = std::memcmp(&x.weight, &y.weight, sizeof(x.weight)) == 0;
    EXPECT_TRUE(x.v == y.v && x.from == y.from && same_weights) << i;
  }
  // Each of the first faces split at a new vertex on its edge (0, 1).
  Adjacency adjacency = Adjacency::build(start);
  FaceBatch faces;
  for (std::uint32_t f = 0; f < 6; ++f) {
    const Triangle c = start.face(FaceId(f));
    const std::uint32_t ab[2] = {c[0].index, c[1].index};
    const float half = 0.5f;
    const VertexId m = by_batch.add_vertices_on_edges(ab, &half, 1);
    const std::array<glm::vec3, 3> corners = {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)};
    faces.remove(FaceId(f));
    faces.add_from({c[0], m, c[2]}, FaceId(f), corners);
    faces.add_from({m, c[1], c[2]}, FaceId(f), corners);
  }
  by_batch.apply(faces);
  adjacency.apply(by_batch.log());
  test::expect_adjacency_matches_rebuild(adjacency, batched);
  // An end that is not a vertex yet (here: the batch's own first vertex, named by itself) is
  // refused before any change.
  const std::vector<unsigned char> before = mesh_bytes(batched);
  const std::size_t logged = by_batch.log().size();
  const auto next = static_cast<std::uint32_t>(batched.vertex_count());
  const std::uint32_t bad[4] = {0, 1, 2, next + 1};
  const float ts[2] = {0.5f, 0.5f};
  EXPECT_THROW(by_batch.add_vertices_on_edges(bad, ts, 2), Error);
  EXPECT_EQ(mesh_bytes(batched), before);
  EXPECT_EQ(by_batch.log().size(), logged);
}

TEST(MeshEditorTest, a_vertex_batch_with_a_bad_end_late_in_it_changes_nothing) {
  // More vertices than the editor grows its arrays for at once (64), the one bad end in the
  // second group: refused before the first group is added, every array and the log unchanged.
  SurfaceMesh mesh = test::make_grid(4, 3);
  MeshEditor editor(mesh);
  const auto nv = static_cast<std::uint32_t>(mesh.vertex_count());
  std::vector<std::uint32_t> ends;
  std::vector<float> t;
  for (std::uint32_t i = 0; i < 100; ++i) {
    ends.insert(ends.end(), {i % nv, (i + 1) % nv});
    t.push_back(0.25f);
  }
  ends[2 * 80 + 1] = nv + 80;  // the vertex being made itself: not a vertex yet
  const std::vector<unsigned char> before = mesh_bytes(mesh);
  EXPECT_THROW(editor.add_vertices_on_edges(ends.data(), t.data(), t.size()), Error);
  EXPECT_EQ(mesh.vertex_count(), nv);
  EXPECT_EQ(mesh_bytes(mesh), before);
  EXPECT_EQ(editor.log().size(), 0u);
  // One below it is the vertex made just before: accepted.
  ends[2 * 80 + 1] = nv + 79;
  EXPECT_EQ(editor.add_vertices_on_edges(ends.data(), t.data(), t.size()), VertexId(nv));
  EXPECT_EQ(editor.log().size(), t.size());
  // No vertices: nothing changes, the next vertex's id is returned.
  EXPECT_EQ(editor.add_vertices_on_edges(nullptr, nullptr, 0), VertexId(nv + 100));
  EXPECT_EQ(editor.log().size(), t.size());
  // A triangle corner that is not a vertex: refused too.
  const std::vector<unsigned char> after = mesh_bytes(mesh);
  const Triangle beyond = {VertexId(0), VertexId(1), VertexId(nv + 100)};
  EXPECT_THROW(editor.add_vertex_in_triangle(beyond, glm::vec3(1.0f / 3)), Error);
  EXPECT_EQ(mesh_bytes(mesh), after);
  EXPECT_EQ(editor.log().size(), t.size());
}

TEST(MeshEditorTest, parentless_faces_in_one_call_equal_them_one_by_one) {
  // The same mesh (default corner and face attributes) and the same log as add_face face by
  // face; a corner that is not a vertex, late in the list, is refused before any change.
  SurfaceMesh start = test::make_grid(3, 2);
  start.face_attrs().add<std::uint8_t>(attr::kCutSurface);
  start.corner_attrs().add<glm::vec4>(attr::kTangent, glm::vec4(1.0f, 0.0f, 0.0f, -1.0f));
  SurfaceMesh one = start, batched = start;
  MeshEditor by_call(one), by_batch(batched);
  std::vector<Triangle> faces;
  for (std::uint32_t f = 0; f < 5; ++f) {
    const Triangle t = start.face(FaceId(f));
    faces.push_back({t[2], t[1], t[0]});
  }
  for (const Triangle& t : faces) by_call.add_face(t);
  const auto first = static_cast<std::uint32_t>(start.face_slots());
  EXPECT_EQ(by_batch.add_faces(faces.data(), faces.size()), FaceId(first));
  EXPECT_EQ(mesh_bytes(batched), mesh_bytes(one));
  ASSERT_EQ(by_batch.log().size(), faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const auto& x = std::get<FaceAdded>(by_batch.log().edits[i]);
    const auto& y = std::get<FaceAdded>(by_call.log().edits[i]);
    EXPECT_TRUE(x.f == y.f && x.parent == y.parent && x.vertices == y.vertices) << i;
    EXPECT_EQ(x.f, FaceId(first + static_cast<std::uint32_t>(i)));
  }
  const std::vector<unsigned char> before = mesh_bytes(batched);
  faces[3][1] = VertexId(static_cast<std::uint32_t>(start.vertex_count()));
  EXPECT_THROW(by_batch.add_faces(faces.data(), faces.size()), Error);
  EXPECT_EQ(mesh_bytes(batched), before);
  EXPECT_EQ(by_batch.log().size(), 5u);
}

TEST(MeshEditorTest, a_face_batch_removing_a_face_twice_changes_nothing) {
  // The second removal would find the face deleted: the batch is refused before any change,
  // whether the two removals are next to each other or apart, with faces queued between them.
  SurfaceMesh mesh = test::make_grid(3, 2);
  MeshEditor editor(mesh);
  const std::vector<unsigned char> before = mesh_bytes(mesh);
  const std::array<glm::vec3, 3> same = {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)};
  for (const std::vector<std::uint32_t>& removals : {std::vector<std::uint32_t>{2, 2}, {1, 4, 3, 4, 0}}) {
    FaceBatch batch;
    for (std::uint32_t f : removals) {
      batch.remove(FaceId(f));
      batch.add_from(mesh.face(FaceId(f)), FaceId(f), same);
    }
    try {
      editor.apply(batch);
      ADD_FAILURE() << "no throw";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("queued for removal twice"), std::string::npos) << e.what();
    }
    EXPECT_EQ(mesh_bytes(mesh), before);
    EXPECT_EQ(editor.log().size(), 0u);
    EXPECT_FALSE(batch.empty());  // kept for the caller
  }
}

TEST(MeshEditorTest, an_ascending_face_batch_removing_a_dead_or_missing_face_changes_nothing) {
  // Removals in ascending order take the one-pass check: a face already deleted or past the
  // last slot is refused there, before any change.
  SurfaceMesh mesh = test::make_grid(3, 2);
  MeshEditor editor(mesh);
  editor.remove_face(FaceId(2));
  const std::vector<unsigned char> before = mesh_bytes(mesh);
  const std::size_t logged = editor.log().size();
  const std::array<glm::vec3, 3> same = {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)};
  const auto slots = static_cast<std::uint32_t>(mesh.face_slots());
  for (const std::vector<std::uint32_t>& removals : {std::vector<std::uint32_t>{1, 2, 3}, {0, 1, slots}}) {
    FaceBatch batch;
    for (std::uint32_t f : removals) {
      batch.remove(FaceId(f));
      batch.add_from(mesh.face(FaceId(f < slots ? f : 0)), FaceId(f < slots ? f : 0), same);
    }
    EXPECT_THROW(editor.apply(batch), Error);
    EXPECT_EQ(mesh_bytes(mesh), before);
    EXPECT_EQ(editor.log().size(), logged);
    EXPECT_FALSE(batch.empty());
  }
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

// Influences already checked (finite weights >= 0, positive weights on distinct joints) come out of
// renormalize_influences bit for bit as out of normalize_influences: summing to 1, not, or to 0,
// over 4, 8 and 3 slots.
TEST(MeshEditorTest, renormalize_influences_equals_normalize_influences_on_checked_influences) {
  std::mt19937 rng(19);
  std::uniform_real_distribution<float> weight(0.0f, 1.0f);
  for (int slots : {4, 8, 3})
    for (int round = 0; round < 2000; ++round) {
      std::uint16_t j[8], j2[8];
      float w[8], w2[8];
      for (int i = 0; i < slots; ++i) {
        j[i] = static_cast<std::uint16_t>(round % 3 == 0 ? 7 * i : (13 * i + round) % 500);  // distinct
        w[i] = round % 5 == 0 ? 0.0f : (round % 4 == 0 && i % 2 ? 0.0f : weight(rng));
      }
      if (round % 7 == 1) {  // summing to 1 exactly: kept as they are
        float rest = 1.0f;
        for (int i = 0; i + 1 < slots; ++i) rest -= (w[i] = std::ldexp(std::floor(w[i] * 64.0f), -9));
        w[slots - 1] = rest;
      }
      std::copy(j, j + slots, j2);
      std::copy(w, w + slots, w2);
      EXPECT_EQ(renormalize_influences(j, w, slots), normalize_influences(j2, w2, slots));
      EXPECT_EQ(std::memcmp(j, j2, sizeof(j[0]) * std::size_t(slots)), 0);
      EXPECT_EQ(std::memcmp(w, w2, sizeof(w[0]) * std::size_t(slots)), 0);
    }
}

namespace {

// Bytes of the corner and face attributes of face `f`.
std::vector<unsigned char> face_bytes(const SurfaceMesh& mesh, FaceId f) {
  std::vector<unsigned char> out;
  auto put = [&](const AttributeSet& set, std::size_t i) {
    for (const std::string& name : set.names()) {
      const AttributeArrayBase& a = *set.base(name);
      const auto* b = static_cast<const unsigned char*>(a.element_data(i));
      out.insert(out.end(), b, b + a.element_bytes());
    }
  };
  put(mesh.face_attrs(), f.index);
  for (int k = 0; k < 3; ++k) put(mesh.corner_attrs(), SurfaceMesh::corner(f, k));
  return out;
}

// Faces made from `start`'s faces 1, 3 and 4, those from 1 and 4 (each by a move of the one
// before) both ways: add_from and a move after it (the face removed and made again from itself
// onto `onto`), and add_moved_from; the one from 3 between them made by add_from alone, so the
// moved faces are two runs. The same live faces with the same bytes.
void expect_moved_equals_add_then_move(const SurfaceMesh& start) {
  const std::array<glm::vec3, 3> thirds = {glm::vec3(0.2f, 0.3f, 0.5f), glm::vec3(0, 0.5f, 0.5f), glm::vec3(0, 0, 1)};
  const std::array<glm::vec3, 3> same = {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)};
  SurfaceMesh twice = start, once = start;
  MeshEditor by_move(twice), direct(once);
  FaceBatch first, second, batch;
  for (std::uint32_t f : {1u, 3u, 4u}) {
    const Triangle t = start.face(FaceId(f));
    first.remove(FaceId(f));
    first.add_from(t, FaceId(f), thirds);
    batch.remove(FaceId(f));
    if (f == 3)
      batch.add_from(t, FaceId(f), thirds);
    else
      batch.add_moved_from({t[1], t[2], t[0]}, FaceId(f), thirds);
  }
  by_move.apply(first);
  for (std::uint32_t f = static_cast<std::uint32_t>(start.face_slots()); f < twice.face_slots(); ++f) {
    if (f == start.face_slots() + 1) continue;  // the face from 3 stays
    const Triangle t = twice.face(FaceId(f));
    second.remove(FaceId(f));
    second.add_from({t[1], t[2], t[0]}, FaceId(f), same);
  }
  by_move.apply(second);
  direct.apply(batch);
  // The moves put the faces from 1 and 4 after the one from 3, the batch keeps them in order:
  // the same faces with the same bytes, in order of their vertices.
  auto faces_of = [](const SurfaceMesh& mesh) {
    std::vector<std::pair<Triangle, std::vector<unsigned char>>> out;
    mesh.for_each_face([&](FaceId f, const Triangle& t) { out.emplace_back(t, face_bytes(mesh, f)); });
    std::sort(out.begin(), out.end());
    return out;
  };
  const auto from_twice = faces_of(twice), from_once = faces_of(once);
  ASSERT_EQ(from_twice.size(), from_once.size());
  for (std::size_t i = 0; i < from_once.size(); ++i) {
    EXPECT_EQ(from_twice[i].first, from_once[i].first) << i;
    EXPECT_EQ(from_twice[i].second, from_once[i].second) << i;
  }
}

}  // namespace

TEST(MeshEditorTest, a_face_made_moved_equals_the_face_made_then_moved) {
  // Normals and tangents of other lengths (normalised twice either way), a zero normal, a -0 and
  // a cut-surface flag; then values a move changes (an infinite uv, a -0 that stays after the
  // first normalisation) and an attribute type the editor does not know: the exact way then.
  SurfaceMesh start = test::make_grid(3, 2);
  start.corner_attrs().add<glm::vec4>(attr::kTangent, glm::vec4(3.0f, 0.1f, 0.0f, -1.0f));
  start.face_attrs().add<std::uint8_t>(attr::kCutSurface);
  start.face_attrs().get<std::uint8_t>(attr::kCutSurface)[4] = 1;
  auto& normals = start.corner_attrs().get<glm::vec3>(attr::kNormal);
  for (std::size_t c = 0; c < normals.size(); ++c) normals[c] = glm::vec3(0.3f * float(c), 1.7f, -0.1f * float(c % 5));
  normals[SurfaceMesh::corner(FaceId(4), 1)] = glm::vec3(0.0f);
  normals[SurfaceMesh::corner(FaceId(1), 0)] = glm::vec3(-0.0f, 2.0f, 0.0f);
  expect_moved_equals_add_then_move(start);
  SurfaceMesh infinite = start;
  infinite.corner_attrs().get<glm::vec2>(attr::kUv0)[SurfaceMesh::corner(FaceId(4), 2)].x = INFINITY;
  expect_moved_equals_add_then_move(infinite);
  SurfaceMesh tiny = start;
  auto& n = tiny.corner_attrs().get<glm::vec3>(attr::kNormal);
  for (int k = 0; k < 3; ++k) n[SurfaceMesh::corner(FaceId(1), k)] = glm::vec3(-1e-44f, 1e30f, 0.0f);
  expect_moved_equals_add_then_move(tiny);
  SurfaceMesh other_type = start;
  other_type.corner_attrs().add<double>("c:test_double", -0.0);
  expect_moved_equals_add_then_move(other_type);
}

}  // namespace deepcut
