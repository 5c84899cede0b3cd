// SPDX-License-Identifier: MIT
#include "deepcut/core/adjacency.h"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/mesh_editor.h"
#include "fixtures.h"

namespace deepcut {
namespace {

// Random local edits through MeshEditor: 1-to-3 face splits, edge splits (both faces),
// vertex splits with a face re-attached, and face removals.
void random_edit(SurfaceMesh& mesh, MeshEditor& editor, const Adjacency& adj, std::mt19937& rng) {
  std::vector<FaceId> live;
  mesh.for_each_face([&](FaceId f, const Triangle&) { live.push_back(f); });
  if (live.empty()) return;
  const FaceId f = live[std::uniform_int_distribution<std::size_t>(0, live.size() - 1)(rng)];
  const Triangle t = mesh.face(f);
  switch (std::uniform_int_distribution<int>(0, 3)(rng)) {
    case 0: {  // 1-to-3
      const glm::vec3 b(0.3f, 0.3f, 0.4f);
      const VertexId c = editor.add_vertex_in_triangle(t, b);
      editor.remove_face(f);
      const glm::vec3 e0(1, 0, 0), e1(0, 1, 0), e2(0, 0, 1);
      editor.add_face_from({t[0], t[1], c}, f, {e0, e1, b});
      editor.add_face_from({t[1], t[2], c}, f, {e1, e2, b});
      editor.add_face_from({t[2], t[0], c}, f, {e2, e0, b});
      break;
    }
    case 1: {  // split edge t0-t1 in every face that uses it
      const VertexId a = t[0], b = t[1];
      const auto faces = adj.edge_faces(a, b);
      const VertexId m = editor.add_vertex_on_edge(a, b, 0.4f);
      for (FaceId g : faces) {
        const Triangle gt = mesh.face(g);
        int ka = 0;
        while (gt[ka] != a) ++ka;
        const int kb = gt[(ka + 1) % 3] == b ? (ka + 1) % 3 : (ka + 2) % 3;
        const int kc = 3 - ka - kb;
        glm::vec3 ua(0.0f), ub(0.0f), uc(0.0f), um(0.0f);
        ua[ka] = 1;
        ub[kb] = 1;
        uc[kc] = 1;
        um[ka] = 0.6f;
        um[kb] = 0.4f;
        editor.remove_face(g);
        // Keep the orientation of g: walk its corners, replacing edge (a,b) by (a,m,b).
        if (kb == (ka + 1) % 3) {
          editor.add_face_from({a, m, gt[kc]}, g, {ua, um, uc});
          editor.add_face_from({m, b, gt[kc]}, g, {um, ub, uc});
        } else {
          editor.add_face_from({b, m, gt[kc]}, g, {ub, um, uc});
          editor.add_face_from({m, a, gt[kc]}, g, {um, ua, uc});
        }
      }
      break;
    }
    case 2: {  // detach a face at one vertex (tear-like)
      const VertexId copy = editor.split_vertex(t[0]);
      editor.remove_face(f);
      editor.add_face_from({copy, t[1], t[2]}, f, {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)});
      break;
    }
    default:
      editor.remove_face(f);
  }
}

}  // namespace

TEST(AdjacencyTest, grid_neighbourhoods_and_boundary) {
  const SurfaceMesh mesh = test::make_grid(3, 3);
  const Adjacency adj = Adjacency::build(mesh);
  EXPECT_EQ(adj.boundary_edges().size(), 12u);
  EXPECT_TRUE(adj.nonmanifold_edges().empty());
  EXPECT_EQ(adj.component_count(), 1u);
  EXPECT_EQ(adj.vertex_neighbors(VertexId(5)).size(), 6u);  // interior vertex of a regular grid
  EXPECT_EQ(adj.face_neighbors(FaceId(8)).size(), 3u);
  // The UV seam sits between columns 1 and 2 (x = 2/3): three vertical edges.
  EXPECT_EQ(adj.seam_edges(mesh).size(), 3u);
  const SurfaceMesh grid2 = test::make_grid(2, 2);
  EXPECT_EQ(Adjacency::build(grid2).seam_edges(grid2).size(), 2u);
}

TEST(AdjacencyTest, closed_tube_has_no_boundary_and_detects_nonmanifold_edges) {
  SurfaceMesh mesh = test::make_tube(8, 2);
  Adjacency adj = Adjacency::build(mesh);
  EXPECT_TRUE(adj.boundary_edges().empty());
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) EXPECT_FALSE(adj.vertex_faces(VertexId(v)).empty());
  // A fin on an existing edge makes it non-manifold.
  const Triangle t = mesh.face(FaceId(0));
  MeshEditor editor(mesh);
  const VertexId tip = editor.add_vertex_in_triangle(t, glm::vec3(1.0f / 3));
  editor.move_vertex(tip, mesh.position(tip) + glm::vec3(0, 0, 5));
  editor.add_face({t[0], t[1], tip});
  adj.apply(editor.log());
  EXPECT_EQ(adj.nonmanifold_edges().size(), 1u);
  test::expect_adjacency_matches_rebuild(adj, mesh);
}

TEST(AdjacencyTest, incremental_equals_rebuild_after_random_edits) {
  for (unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    SurfaceMesh mesh = seed == 2 ? test::make_tube(12, 6) : test::make_grid(6, 5);
    Adjacency adj = Adjacency::build(mesh);
    std::mt19937 rng(seed);
    for (int step = 0; step < 300; ++step) {
      MeshEditor editor(mesh);
      random_edit(mesh, editor, adj, rng);
      adj.apply(editor.take_log());
      if (step % 25 == 0 || step == 299) {
        SCOPED_TRACE("step " + std::to_string(step));
        test::expect_adjacency_matches_rebuild(adj, mesh);
        test::expect_valid(mesh);
      }
    }
  }
}

TEST(AdjacencyTest, incremental_equals_rebuild_on_every_asset) {
  for (const auto& path : test::asset_models()) {
    SCOPED_TRACE(path);
    Model model = read_gltf(path);
    for (auto& mesh : model.meshes)
      for (auto& prim : mesh.primitives) {
        Adjacency adj = Adjacency::build(prim.mesh);
        std::mt19937 rng(7);
        for (int step = 0; step < 100; ++step) {
          MeshEditor editor(prim.mesh);
          random_edit(prim.mesh, editor, adj, rng);
          adj.apply(editor.take_log());
        }
        test::expect_adjacency_matches_rebuild(adj, prim.mesh);
      }
  }
}

// The vertices an edit adds keep their lists in a shared pool, with room for eight faces: a fan
// of twenty faces around one of them outgrows that room twice, and copies taken along the way
// (with or without reserve) must follow later edits like the original.
TEST(AdjacencyTest, added_vertex_lists_grow_shrink_and_copy) {
  SurfaceMesh mesh = test::make_grid(6, 5);
  Adjacency adj = Adjacency::build(mesh);
  std::vector<FaceId> fan;
  {
    MeshEditor editor(mesh);
    const VertexId hub = editor.add_vertex_in_triangle(mesh.face(FaceId(0)), glm::vec3(1.0f / 3.0f));
    for (std::uint32_t i = 0; i < 20; ++i)
      fan.push_back(editor.add_face({hub, VertexId(i + 1), VertexId(i + 2)}));
    adj.apply(editor.take_log());
    const VertexFaces faces = adj.vertex_faces(hub);
    EXPECT_EQ(std::vector<FaceId>(faces.begin(), faces.end()), fan);
  }
  test::expect_adjacency_matches_rebuild(adj, mesh);
  Adjacency reserved = adj;
  reserved.reserve(mesh.vertex_count() + 64, mesh.face_slots() + 128);
  for (Adjacency* a : {&adj, &reserved}) {
    SurfaceMesh edited = mesh;
    MeshEditor editor(edited);
    for (std::size_t i = 0; i < fan.size(); i += 3) editor.remove_face(fan[i]);
    a->apply(editor.take_log());
    test::expect_adjacency_matches_rebuild(*a, edited);
  }
}

// A removal takes the face out of every corner's list wherever it sits (first, middle, last, the
// only one), for the vertices `build` saw and the ones an edit added, and leaves a list alone
// where the face is not (the second corner of a face using a vertex twice, listed once): each
// step's lists equal a rebuild's, in order.
TEST(AdjacencyTest, removals_anywhere_in_a_list_match_a_rebuild) {
  SurfaceMesh mesh = test::make_grid(2, 2);  // vertex 4 in the middle: faces 0, 1, 3, 4, 6, 7
  Adjacency adj = Adjacency::build(mesh);
  auto edit = [&](auto&& change) {
    MeshEditor editor(mesh);
    change(editor);
    adj.apply(editor.take_log());
    test::expect_adjacency_matches_rebuild(adj, mesh);
  };
  const VertexId mid(4);
  ASSERT_EQ(adj.vertex_faces(mid).size(), 6u);
  for (const std::uint32_t f : {7u, 0u, 4u}) {  // last, first, middle
    SCOPED_TRACE("face " + std::to_string(f));
    edit([&](MeshEditor& e) { e.remove_face(FaceId(f)); });
  }
  // A fold using the middle vertex twice: removed while the newest face there (the second visit
  // of the vertex sees a list whose last face is below it), then while an older one.
  FaceId fold;
  edit([&](MeshEditor& e) { fold = e.add_face({mid, mid, VertexId(5)}); });
  edit([&](MeshEditor& e) { e.remove_face(fold); });
  edit([&](MeshEditor& e) {
    fold = e.add_face({mid, mid, VertexId(5)});
    e.add_face({mid, VertexId(5), VertexId(2)});
  });
  edit([&](MeshEditor& e) { e.remove_face(fold); });
  // An added vertex's list (the shared pool): its last, first and middle faces, then the rest.
  VertexId hub;
  std::vector<FaceId> fan;
  edit([&](MeshEditor& e) {
    hub = e.add_vertex_in_triangle(mesh.face(FaceId(2)), glm::vec3(1.0f / 3.0f));
    for (const std::uint32_t v : {0u, 1u, 2u, 5u, 8u})
      fan.push_back(e.add_face({hub, VertexId(v), VertexId(v + 1)}));
  });
  for (const std::size_t i : {4u, 0u, 2u, 1u, 3u}) {
    SCOPED_TRACE("fan face " + std::to_string(i));
    edit([&](MeshEditor& e) { e.remove_face(fan[i]); });
  }
  EXPECT_TRUE(adj.vertex_faces(hub).empty());
}

}  // namespace deepcut
