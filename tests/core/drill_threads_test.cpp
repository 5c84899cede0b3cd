// SPDX-License-Identifier: MIT
// The drill plans its crossed faces in parallel chunks (core/src/ops/drill/rim_faces.h) and
// makes the edits in candidate order: the result is the same whatever the thread count, and
// whatever was drilled before on the same threads (their planning lists are reused). A big
// drill's lists give their memory back when it ends.
#include <gtest/gtest.h>

#include <initializer_list>
#include <utility>
#include <variant>
#include <vector>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/ops/drill.h"
#include "deepcut/core/posed_model.h"
#include "fixtures.h"
#include "ops/drill/rim_faces.h"
#include "thread_count.h"

namespace deepcut {
namespace {

using test::ThreadCount;

struct Drilled {
  SurfaceMesh mesh;
  DrillResult result;
};

Drilled drill_with(std::size_t threads, const SurfaceMesh& input, const Cylinder& cyl, bool wall,
                   int rim_edges = 32) {
  ThreadCount guard(threads);
  Drilled d{input, {}};
  DrillOptions options;
  options.wall = wall;
  options.min_rim_edges = rim_edges;
  d.result = drill_mesh(d.mesh, PosedMesh::at_positions(input), cyl, options);
  return d;
}

void expect_same(const Drilled& a, const Drilled& b) {
  EXPECT_EQ(a.mesh.faces(), b.mesh.faces());
  EXPECT_EQ(a.mesh.positions(), b.mesh.positions());
  EXPECT_EQ(a.result.log.size(), b.result.log.size());
  EXPECT_EQ(a.result.added_posed, b.result.added_posed);
  ASSERT_EQ(a.result.holes.size(), b.result.holes.size());
  for (std::size_t h = 0; h < b.result.holes.size(); ++h)
    EXPECT_EQ(a.result.holes[h].rim, b.result.holes[h].rim);
  EXPECT_EQ(a.result.triangles_added, b.result.triangles_added);
  EXPECT_EQ(a.result.wall_triangles, b.result.wall_triangles);
}

TEST(DrillThreadsTest, the_result_does_not_depend_on_the_thread_count) {
  CactusOptions options;
  options.target_triangles = 40000;  // a hole through the trunk crosses many planning chunks
  const Model model = make_cactus(options);
  const SurfaceMesh& input = model.meshes[0].primitives[0].mesh;
  const BoundingBox box = input.bounds();
  const glm::vec3 c = 0.5f * (box.min + box.max);
  for (const float radius : {0.03f, 0.12f})
    for (const bool wall : {false, true}) {
      const Cylinder cyl{{c.x, c.y, box.max.z + 1.0f}, {c.x - 0.1f, c.y + 0.2f, box.min.z - 1.0f},
                         radius * box.diagonal()};
      const Drilled one = drill_with(1, input, cyl, wall);
      ASSERT_EQ(one.result.status, OpStatus::Ok);
      ASSERT_GT(one.result.triangles_added, 100u);
      for (const std::size_t threads : {2u, 3u, 8u}) {
        const Drilled many = drill_with(threads, input, cyl, wall);
        SCOPED_TRACE(testing::Message() << threads << " threads, radius " << radius << ", wall " << wall);
        expect_same(many, one);
      }
    }
}

// The saddle of DrillTest.an_old_boundary_edge_at_a_split_vertex_is_not_rim (drill_rim_test.cpp)
// without walls: its vertex is pinched, split once, and the rims are traced again through the
// copy, the same whatever the thread count.
TEST(DrillThreadsTest, a_pinch_split_and_its_second_rim_trace_do_not_depend_on_the_thread_count) {
  SurfaceMesh input;
  const VertexId v = input.add_vertex({0, 0, 0}), w = input.add_vertex({0.5f, 0, 0});
  const VertexId py = input.add_vertex({0, 1, -1}), mx = input.add_vertex({-1, 0, 1}),
                 my = input.add_vertex({0, -1, -1}), my2 = input.add_vertex({0.3f, -1, -1}),
                 px = input.add_vertex({1, 0, 1});
  input.add_face(v, my, my2);
  input.add_face(v, mx, my);
  input.add_face(v, my2, px);
  input.add_face(v, w, py);
  input.add_face(v, py, mx);
  const Cylinder cyl{{-2, 0, 0.6f}, {2, 0, 0.6f}, 0.6f};
  const Drilled one = drill_with(1, input, cyl, false);
  ASSERT_EQ(one.result.status, OpStatus::Ok);
  std::size_t splits = 0;
  for (const Edit& e : one.result.log.edits) splits += std::holds_alternative<VertexSplit>(e) ? 1 : 0;
  EXPECT_EQ(splits, 1u);
  for (const std::size_t threads : {2u, 8u}) {
    SCOPED_TRACE(testing::Message() << threads << " threads");
    expect_same(drill_with(threads, input, cyl, false), one);
  }
}

// The calling thread's planning lists: none holds more than kKeptBytes.
void expect_no_big_plan_lists() {
  using drill::PlanChunk;
  for (const PlanChunk& c : PlanChunk::local()) {
    EXPECT_LE(c.pts.capacity() * sizeof(c.pts[0]), PlanChunk::kKeptBytes);
    EXPECT_LE(c.tris.capacity() * sizeof(c.tris[0]), PlanChunk::kKeptBytes);
    EXPECT_LE(c.polys.capacity() * sizeof(c.polys[0]), PlanChunk::kKeptBytes);
  }
}

// PlanChunk::reused hands out this thread's chunks empty; a list grown past kKeptBytes gives its
// memory back (at give_back_big, or at the next reuse), a smaller one keeps it.
TEST(PlanChunkTest, lists_above_the_threshold_give_their_memory_back) {
  using drill::PlanChunk;
  const std::size_t big = 2 * PlanChunk::kKeptBytes / sizeof(drill::LocalPoint);
  {
    std::vector<PlanChunk>& chunks = PlanChunk::reused(2);
    ASSERT_EQ(chunks.size(), 2u);
    EXPECT_EQ(&chunks, &PlanChunk::local());
    chunks[0].pts.resize(big);
    chunks[1].pts.resize(8);
    chunks[1].polys.resize(8);
    const std::size_t small = chunks[1].pts.capacity();
    PlanChunk::give_back_big(chunks);
    EXPECT_LE(chunks[0].pts.capacity() * sizeof(drill::LocalPoint), PlanChunk::kKeptBytes);
    EXPECT_EQ(chunks[1].pts.capacity(), small);
    EXPECT_EQ(chunks[1].pts.size(), 8u) << "give_back_big leaves small lists as they are";
  }
  PlanChunk::local()[0].pts.resize(big);
  for (int again = 0; again < 2; ++again) {
    std::vector<PlanChunk>& chunks = PlanChunk::reused(1);
    ASSERT_EQ(chunks.size(), 1u);
    EXPECT_TRUE(chunks[0].pts.empty());
    EXPECT_TRUE(chunks[0].polys.empty());
    EXPECT_LE(chunks[0].pts.capacity() * sizeof(drill::LocalPoint), PlanChunk::kKeptBytes);
    chunks[0].polys.resize(8);
  }
  EXPECT_GE(PlanChunk::local()[0].polys.capacity(), 8u) << "a small list keeps its memory";
}

// A small drill, then a big one (a fine rim across hundreds of faces: its planning lists grow past
// PlanChunk::kKeptBytes, and give their memory back when it ends), then the small one twice: the
// small drill's result is the same each time, whatever the earlier drills left in the lists.
TEST(DrillThreadsTest, the_result_does_not_depend_on_earlier_drills) {
  const SurfaceMesh input = test::make_grid(240, 240);
  const Cylinder small{{0.3f, 0.3f, -1.0f}, {0.3f, 0.3f, 1.0f}, 0.02f};
  const Cylinder big{{0.5f, 0.5f, -1.0f}, {0.5f, 0.5f, 1.0f}, 0.45f};
  for (const std::size_t threads : {1u, 3u}) {
    SCOPED_TRACE(testing::Message() << threads << " threads");
    const Drilled first = drill_with(threads, input, small, false);
    ASSERT_EQ(first.result.status, OpStatus::Ok);
    const Drilled after_big = drill_with(threads, input, big, false, 1024);
    ASSERT_GT(after_big.result.intersection_points, 500u);
    expect_no_big_plan_lists();
    for (int again = 0; again < 2; ++again) expect_same(drill_with(threads, input, small, false), first);
  }
}

// The Steiner rule of a crossed edge (EdgeCut::takes_steiner): exactly one candidate face on each
// side of the edge, neither of bad shape; the order the faces are filed in does not matter.
TEST(EdgeCutTest, steiner_points_need_one_good_face_on_each_side) {
  using drill::EdgeCut;
  const VertexId lo(3), hi(7);
  auto filed = [&](std::initializer_list<std::pair<bool, bool>> faces) {  // (lo -> hi, bad)
    EdgeCut e;
    for (const auto& [forward, bad] : faces) {
      if (forward) e.file_side(lo, hi, bad);
      else e.file_side(hi, lo, bad);
    }
    return e.takes_steiner();
  };
  EXPECT_TRUE(filed({{true, false}, {false, false}}));
  EXPECT_TRUE(filed({{false, false}, {true, false}}));
  EXPECT_FALSE(EdgeCut().takes_steiner()) << "no face";
  EXPECT_FALSE(filed({{true, false}})) << "a boundary edge";
  EXPECT_FALSE(filed({{false, false}})) << "a boundary edge";
  EXPECT_FALSE(filed({{true, false}, {true, false}})) << "two faces on one side";
  EXPECT_FALSE(filed({{true, false}, {false, false}, {true, false}})) << "three faces";
  EXPECT_FALSE(filed({{true, true}, {false, false}})) << "a bad face";
  EXPECT_FALSE(filed({{true, false}, {false, true}})) << "a bad face";
}

}  // namespace
}  // namespace deepcut
