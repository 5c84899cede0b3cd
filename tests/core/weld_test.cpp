// SPDX-License-Identifier: MIT
#include "deepcut/core/weld.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <utility>
#include <vector>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/operation_room.h"
#include "deepcut/core/parallel.h"
#include "fixtures.h"

namespace deepcut {
namespace {

// The attributes the weld tests carry from a mesh into a new one: joints, weights and UVs.
struct CarriedAttributes {
  CarriedAttributes(const SurfaceMesh& from, SurfaceMesh& to)
      : j(to.vertex_attrs().add<glm::u16vec4>(attr::kJoints0)),
        w(to.vertex_attrs().add<glm::vec4>(attr::kWeights0)),
        uv(to.corner_attrs().add<glm::vec2>(attr::kUv0)),
        sj(from.vertex_attrs().get<glm::u16vec4>(attr::kJoints0)),
        sw(from.vertex_attrs().get<glm::vec4>(attr::kWeights0)),
        suv(from.corner_attrs().get<glm::vec2>(attr::kUv0)) {}
  void vertex(VertexId to, std::uint32_t from) {
    j[to.index] = sj[from];
    w[to.index] = sw[from];
  }
  void corners(FaceId to, FaceId from) {
    for (int k = 0; k < 3; ++k) uv[SurfaceMesh::corner(to, k)] = suv[SurfaceMesh::corner(from, k)];
  }
  AttributeArray<glm::u16vec4>& j;
  AttributeArray<glm::vec4>& w;
  AttributeArray<glm::vec2>& uv;
  const AttributeArray<glm::u16vec4>& sj;
  const AttributeArray<glm::vec4>& sw;
  const AttributeArray<glm::vec2>& suv;
};

// Every corner its own vertex, as a non-indexed glTF primitive stores it.
SurfaceMesh unweld(const SurfaceMesh& mesh) {
  SurfaceMesh out;
  CarriedAttributes carried(mesh, out);
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    VertexId v[3];
    for (int k = 0; k < 3; ++k) {
      v[k] = out.add_vertex(mesh.position(t[k]));
      carried.vertex(v[k], t[k].index);
    }
    carried.corners(out.add_face(v[0], v[1], v[2]), f);
  });
  return out;
}

}  // namespace

TEST(WeldTest, merges_split_corners_back_into_the_grid_and_keeps_the_uv_seam) {
  const SurfaceMesh grid = test::make_grid(4, 3);
  SurfaceMesh mesh = unweld(grid);
  ASSERT_EQ(mesh.vertex_count(), 3 * grid.face_count());
  const WeldReport r = weld(mesh);
  EXPECT_EQ(mesh.vertex_count(), grid.vertex_count());
  EXPECT_EQ(r.merged, 3 * grid.face_count() - grid.vertex_count());
  EXPECT_EQ(r.kept_apart, 0u);
  EXPECT_EQ(mesh.face_count(), grid.face_count());
  const Adjacency adj = Adjacency::build(mesh);
  EXPECT_EQ(adj.component_count(), 1u);
  EXPECT_EQ(adj.seam_edges(mesh).size(), Adjacency::build(grid).seam_edges(grid).size());
  EXPECT_NEAR(mesh.area(), grid.area(), 1e-6);
}

TEST(WeldTest, never_merges_different_skin_weights_and_drops_unused_vertices) {
  SurfaceMesh mesh = unweld(test::make_grid(1, 1));  // two triangles, six vertices
  auto& w = mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0);
  w[3] = {0.3f, 0.7f, 0.0f, 0.0f};  // vertex 3 duplicates vertex 0's position with other weights
  mesh.add_vertex({9, 9, 9});         // unreferenced
  mesh.positions()[4] = mesh.positions()[4] * -0.0f + mesh.positions()[4];  // -0 folds into +0
  const WeldReport r = weld(mesh);
  EXPECT_EQ(mesh.vertex_count(), 5u);
  EXPECT_EQ(r.kept_apart, 1u);
  EXPECT_EQ(r.dropped, 1u);
}

}  // namespace deepcut

namespace deepcut {

namespace {

// The weld of `split` on 1, 2 and 3 threads: the welded meshes and their reports, in that order.
std::pair<std::vector<SurfaceMesh>, std::vector<WeldReport>> weld_on_1_2_and_3_threads(
    const SurfaceMesh& split) {
  std::vector<SurfaceMesh> welded;
  std::vector<WeldReport> reports;
  const std::size_t saved = thread_count();
  for (std::size_t threads : {1u, 2u, 3u}) {
    set_thread_count(threads);
    SurfaceMesh mesh = split;
    reports.push_back(weld(mesh));
    welded.push_back(std::move(mesh));
  }
  set_thread_count(saved);
  return {std::move(welded), std::move(reports)};
}

}  // namespace

TEST(WeldTest, the_result_does_not_depend_on_the_thread_count) {
  // Large enough for several parallel chunks.
  const SurfaceMesh split = unweld(test::make_grid(160, 120));
  const auto [welded, reports] = weld_on_1_2_and_3_threads(split);
  for (std::size_t i = 1; i < welded.size(); ++i) {
    EXPECT_EQ(welded[i].faces(), welded[0].faces());
    EXPECT_EQ(welded[i].positions(), welded[0].positions());
    EXPECT_EQ(welded[i].corner_attrs().get<glm::vec2>(attr::kUv0).data(),
              welded[0].corner_attrs().get<glm::vec2>(attr::kUv0).data());
    EXPECT_EQ(welded[i].vertex_attrs().get<glm::vec4>(attr::kWeights0).data(),
              welded[0].vertex_attrs().get<glm::vec4>(attr::kWeights0).data());
    EXPECT_EQ(reports[i].merged, reports[0].merged);
  }
  EXPECT_EQ(welded[0].vertex_count(), 161u * 121u);
  EXPECT_EQ(reports[0].merged, split.vertex_count() - 161u * 121u);
}

// Vertices at one position with different weights, spread over many parallel chunks: the weld
// finds the same classes and counts the same vertices kept apart whatever the thread count, and
// the count is the classes less the positions.
TEST(WeldTest, vertices_kept_apart_are_the_same_whatever_the_thread_count) {
  SurfaceMesh split = unweld(test::make_grid(160, 120));
  auto& w = split.vertex_attrs().get<glm::vec4>(attr::kWeights0);
  for (std::uint32_t v = 0; v < split.vertex_count(); v += 7) w[v] = {0.25f, 0.75f, 0.0f, 0.0f};
  std::set<std::array<float, 3>> positions;
  std::set<std::array<float, 7>> classes;
  for (std::uint32_t v = 0; v < split.vertex_count(); ++v) {
    const glm::vec3 p = split.positions()[v];
    positions.insert({p.x, p.y, p.z});
    classes.insert({p.x, p.y, p.z, w[v].x, w[v].y, w[v].z, w[v].w});
  }
  ASSERT_GT(classes.size(), positions.size());
  const auto [welded, reports] = weld_on_1_2_and_3_threads(split);
  EXPECT_EQ(welded[0].vertex_count(), classes.size());
  EXPECT_EQ(reports[0].kept_apart, classes.size() - positions.size());
  for (std::size_t i = 1; i < welded.size(); ++i) {
    EXPECT_EQ(welded[i].faces(), welded[0].faces());
    EXPECT_EQ(welded[i].positions(), welded[0].positions());
    EXPECT_EQ(welded[i].vertex_attrs().get<glm::vec4>(attr::kWeights0).data(),
              welded[0].vertex_attrs().get<glm::vec4>(attr::kWeights0).data());
    EXPECT_EQ(reports[i].merged, reports[0].merged);
    EXPECT_EQ(reports[i].kept_apart, reports[0].kept_apart);
  }
}

namespace {

// `mesh` (made by unweld) with vertex v renumbered to `to[v]` (distinct numbers; one that none
// takes is an unreferenced vertex), and `extra` unreferenced vertices after them: the same
// faces, corners and vertex attributes.
SurfaceMesh renumbered(const SurfaceMesh& mesh, const std::vector<std::uint32_t>& to, std::size_t extra = 0) {
  const std::size_t n = mesh.vertex_count();
  std::vector<std::uint32_t> from(n == 0 ? 0 : *std::max_element(to.begin(), to.end()) + 1, kInvalidIndex);
  for (std::uint32_t v = 0; v < n; ++v) from[to[v]] = v;
  SurfaceMesh out;
  CarriedAttributes carried(mesh, out);
  std::size_t unused = 0;
  for (std::uint32_t i = 0; i < from.size(); ++i) {
    if (from[i] == kInvalidIndex) {
      out.add_vertex({7.0f, 7.0f, float(unused++)});
      continue;
    }
    carried.vertex(out.add_vertex(mesh.positions()[from[i]]), from[i]);
  }
  for (std::size_t i = 0; i < extra; ++i) out.add_vertex({7.0f, 7.0f, float(unused++)});
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    carried.corners(
        out.add_face(VertexId(to[t[0].index]), VertexId(to[t[1].index]), VertexId(to[t[2].index])), f);
  });
  return out;
}

void expect_same_weld(const SurfaceMesh& a, const WeldReport& ra, const SurfaceMesh& b,
                      const WeldReport& rb) {
  EXPECT_EQ(a.faces(), b.faces());
  EXPECT_EQ(a.positions(), b.positions());
  EXPECT_EQ(a.vertex_attrs().get<glm::vec4>(attr::kWeights0).data(),
            b.vertex_attrs().get<glm::vec4>(attr::kWeights0).data());
  EXPECT_EQ(a.vertex_attrs().get<glm::u16vec4>(attr::kJoints0).data(),
            b.vertex_attrs().get<glm::u16vec4>(attr::kJoints0).data());
  EXPECT_EQ(a.corner_attrs().get<glm::vec2>(attr::kUv0).data(),
            b.corner_attrs().get<glm::vec2>(attr::kUv0).data());
  EXPECT_EQ(ra.merged, rb.merged);
  EXPECT_EQ(ra.dropped, rb.dropped);
  EXPECT_EQ(ra.kept_apart, rb.kept_apart);
  EXPECT_EQ(ra.faces_dropped, rb.faces_dropped);
}

}  // namespace

// Faces that name their vertices in order of first use (as unweld and most files number them)
// take a shorter way to the vertices' order; any other numbering, however far into the faces it
// first breaks that order (or with an unused vertex between used ones), welds to the same mesh,
// the same faces dropped, on any thread count.
TEST(WeldTest, vertices_numbered_in_first_use_order_or_not_weld_the_same) {
  SurfaceMesh split = unweld(test::make_grid(160, 120));  // 38400 faces: several parallel chunks
  auto& w = split.vertex_attrs().get<glm::vec4>(attr::kWeights0);
  auto& j = split.vertex_attrs().get<glm::u16vec4>(attr::kJoints0);
  for (std::uint32_t v = 0; v < split.vertex_count(); v += 11) w[v] = {0.25f, 0.75f, 0.0f, 0.0f};
  // Two faces collapse (a corner at its neighbour's position, joints and weights): dropped.
  for (std::uint32_t f : {100u, 20000u}) {
    split.positions()[3 * f + 1] = split.positions()[3 * f];
    w[3 * f + 1] = w[3 * f];
    j[3 * f + 1] = j[3 * f];
  }
  const WeldOptions drop{WeldKey::PositionAndSkin, /*drop_repeating_faces=*/true};
  const std::size_t n = split.vertex_count();
  std::vector<std::uint32_t> same(n), reversed(n), late(n), gap(n);
  for (std::uint32_t v = 0; v < n; ++v)
    same[v] = late[v] = v, reversed[v] = static_cast<std::uint32_t>(n - 1 - v);
  // Two vertices first used in the last faces swap numbers: the order breaks only there.
  std::swap(late[n - 4], late[n - 2]);
  // Number n / 2 is no face's: the faces name the vertices in order of first use but for a gap.
  for (std::uint32_t v = 0; v < n; ++v) gap[v] = v < n / 2 ? v : v + 1;
  const std::size_t saved = thread_count();
  for (std::size_t threads : {1u, 2u, 3u}) {
    set_thread_count(threads);
    SurfaceMesh expected = split;
    const WeldReport re = weld(expected, drop);
    EXPECT_EQ(re.faces_dropped, 2u);
    for (const auto* to : {&same, &reversed, &late, &gap})
      for (std::size_t extra : {0u, 5u}) {
        SurfaceMesh mesh = renumbered(split, *to, extra);
        const std::size_t unused = mesh.vertex_count() - n;
        const WeldReport r = weld(mesh, drop);
        expect_same_weld(mesh, r, expected,
                         WeldReport{re.merged, re.kept_apart, re.dropped + unused, re.faces_dropped});
      }
  }
  set_thread_count(saved);
}

}  // namespace deepcut

namespace deepcut {

// The key policies, on two triangles that share an edge and were stored apart, as a file does.
TEST(WeldTest, position_key_merges_different_skin_weights_keeping_the_first_users) {
  SurfaceMesh mesh = unweld(test::make_grid(1, 1));  // two triangles, six vertices
  auto& w = mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0);
  for (std::uint32_t v = 0; v < 6; ++v) w[v] = {1.0f - 0.1f * float(v), 0.1f * float(v), 0.0f, 0.0f};
  const std::vector<glm::vec3> positions = mesh.positions();
  const WeldReport r = weld(mesh, {WeldKey::Position});
  EXPECT_EQ(mesh.vertex_count(), 4u);
  EXPECT_EQ(r.merged, 2u);
  EXPECT_EQ(r.kept_apart, 0u);
  EXPECT_EQ(r.dropped, 0u);
  // Vertices 0-2 are the first triangle's, first used in that order: they keep their weights.
  const auto& welded = mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0);
  for (std::uint32_t v = 0; v < 3; ++v) {
    EXPECT_EQ(mesh.positions()[v], positions[v]);
    EXPECT_EQ(welded[v], glm::vec4(1.0f - 0.1f * float(v), 0.1f * float(v), 0.0f, 0.0f));
  }
}

TEST(WeldTest, position_and_skin_key_keeps_different_weights_apart_and_counts_them) {
  SurfaceMesh mesh = unweld(test::make_grid(1, 1));
  auto& w = mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0);
  for (std::uint32_t v = 0; v < 6; ++v) w[v] = {1.0f - 0.1f * float(v), 0.1f * float(v), 0.0f, 0.0f};
  const WeldReport r = weld(mesh, {WeldKey::PositionAndSkin});
  EXPECT_EQ(mesh.vertex_count(), 6u);
  EXPECT_EQ(r.merged, 0u);
  EXPECT_EQ(r.kept_apart, 2u);  // the shared edge's two positions, each stored twice
}

TEST(WeldTest, no_key_merges_nothing_and_only_drops_and_renumbers) {
  SurfaceMesh mesh;
  for (int i = 0; i < 5; ++i) mesh.add_vertex({float(i % 3), float(i / 3), 0.0f});
  mesh.positions()[4] = mesh.positions()[1];  // a duplicate that stays apart
  mesh.add_face(VertexId(2), VertexId(4), VertexId(1));  // vertex 3 is unreferenced
  mesh.add_face(VertexId(0), VertexId(1), VertexId(2));
  const WeldReport r = weld(mesh, {WeldKey::None});
  EXPECT_EQ(r.merged, 0u);
  EXPECT_EQ(r.kept_apart, 0u);
  EXPECT_EQ(r.dropped, 1u);
  ASSERT_EQ(mesh.vertex_count(), 4u);
  // Numbered by first use: 2, 4, 1, 0.
  EXPECT_EQ(mesh.face(FaceId(0)), (Triangle{VertexId(0), VertexId(1), VertexId(2)}));
  EXPECT_EQ(mesh.face(FaceId(1)), (Triangle{VertexId(3), VertexId(2), VertexId(0)}));
  EXPECT_EQ(mesh.positions()[0], glm::vec3(2, 0, 0));
  EXPECT_EQ(mesh.positions()[1], glm::vec3(1, 0, 0));
}

TEST(WeldTest, dropping_repeating_faces_renumbers_by_the_kept_faces_and_drops_what_only_they_used) {
  // Face 0 collapses (its corners 0 and 1 share a position); face 1 is a proper triangle that
  // reuses face 0's position of vertex 0 through vertex 3. Vertex 2 is used by face 0 only.
  SurfaceMesh mesh;
  mesh.add_vertex({0, 0, 0});
  mesh.add_vertex({-0.0f, 0, 0});  // -0 equals +0
  mesh.add_vertex({5, 5, 5});
  mesh.add_vertex({0, 0, 0});
  mesh.add_vertex({1, 0, 0});
  mesh.add_vertex({0, 1, 0});
  mesh.corner_attrs().add<glm::vec2>(attr::kUv0);
  mesh.add_face(VertexId(0), VertexId(1), VertexId(2));
  mesh.add_face(VertexId(4), VertexId(5), VertexId(3));
  auto& uv = mesh.corner_attrs().get<glm::vec2>(attr::kUv0);
  for (std::uint32_t c = 0; c < 6; ++c) uv[c] = glm::vec2(float(c), 0.0f);
  const WeldReport r = weld(mesh, {WeldKey::Position, /*drop_repeating_faces=*/true});
  EXPECT_EQ(r.faces_dropped, 1u);
  EXPECT_EQ(r.dropped, 1u);  // vertex 2
  EXPECT_EQ(r.merged, 2u);   // vertices 1 and 3 into vertex 0
  ASSERT_EQ(mesh.face_count(), 1u);
  ASSERT_EQ(mesh.vertex_count(), 3u);
  EXPECT_EQ(mesh.face(FaceId(0)), (Triangle{VertexId(0), VertexId(1), VertexId(2)}));
  EXPECT_EQ(mesh.positions()[0], glm::vec3(1, 0, 0));
  EXPECT_EQ(mesh.positions()[2], glm::vec3(0, 0, 0));
  const auto& kept_uv = mesh.corner_attrs().get<glm::vec2>(attr::kUv0);
  EXPECT_EQ(kept_uv[0], glm::vec2(3, 0));
  EXPECT_EQ(kept_uv[2], glm::vec2(5, 0));
}

TEST(WeldTest, a_deleted_face_is_left_out_as_if_it_was_never_there) {
  // Without a deleted face the faces are renumbered in their own array; with one they are
  // copied through the list of live faces. Both give the same mesh.
  const SurfaceMesh plain = unweld(test::make_grid(6, 5));
  SurfaceMesh with_deleted = plain;
  VertexId v[3];
  for (int k = 0; k < 3; ++k) v[k] = with_deleted.add_vertex({9.0f, float(k), 0.0f});
  with_deleted.mark_deleted(with_deleted.add_face(v[0], v[1], v[2]));
  SurfaceMesh welded = plain;
  const WeldReport a = weld(welded);
  const WeldReport b = weld(with_deleted);
  EXPECT_EQ(a.merged, b.merged);
  EXPECT_EQ(b.dropped, a.dropped + 3);  // the deleted face's own vertices
  ASSERT_EQ(with_deleted.face_count(), welded.face_count());
  EXPECT_EQ(with_deleted.faces(), welded.faces());
  EXPECT_EQ(with_deleted.positions(), welded.positions());
  EXPECT_EQ(with_deleted.corner_attrs().get<glm::vec2>(attr::kUv0).data(),
            welded.corner_attrs().get<glm::vec2>(attr::kUv0).data());
  EXPECT_GE(with_deleted.faces().capacity(), operation_face_room(with_deleted.face_count()));
}

TEST(WeldTest, rebuilt_vertex_arrays_and_faces_have_the_room_operations_get) {
  for (const WeldKey key : {WeldKey::PositionAndSkin, WeldKey::Position, WeldKey::None}) {
    SCOPED_TRACE(static_cast<int>(key));
    SurfaceMesh mesh = unweld(test::make_grid(6, 5));
    WeldOptions options;
    options.key = key;
    weld(mesh, options);
    EXPECT_GE(mesh.faces().capacity(), operation_face_room(mesh.face_count()));
    const auto& va = mesh.vertex_attrs();
    ASSERT_GE(va.names().size(), 3u);  // positions, joints, weights
    for (const auto& name : va.names()) {
      SCOPED_TRACE(name);
      const AttributeArrayBase& a = *va.base(name);
      EXPECT_GE(a.capacity_bytes(), operation_vertex_room(mesh.vertex_count()) * a.element_bytes());
    }
  }
}

}  // namespace deepcut
