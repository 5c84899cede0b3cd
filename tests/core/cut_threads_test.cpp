// SPDX-License-Identifier: MIT
// A cut's result does not depend on the thread count where its passes split over the pool: the
// posed crossings' bind positions (Placement::place_all) and the sides' faces joined
// chunk by chunk (live_side_faces), and the used-vertex flags of a big mesh cleared and checked in
// parts.
#include <gtest/gtest.h>

#include <cstring>
#include <iterator>
#include <type_traits>
#include <variant>
#include <vector>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/skinning.h"
#include "fixtures.h"
#include "ops/cut/face_lists.h"
#include "tools.h"

namespace deepcut {

// The same edits in the same order: each entry's kind and bytes (every kind is 4-byte fields,
// no padding).
namespace {

void expect_same_log(const EditLog& a, const EditLog& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.edits[i].index(), b.edits[i].index()) << "edit " << i;
    std::visit(
        [&](const auto& x) {
          using T = std::decay_t<decltype(x)>;
          ASSERT_EQ(std::memcmp(&x, &std::get<T>(b.edits[i]), sizeof(T)), 0) << "edit " << i;
        },
        a.edits[i]);
  }
}

}  // namespace

TEST(CutTest, a_posed_cut_with_many_crossings_does_not_depend_on_the_thread_count) {
  // Enough crossings to unpose (256+) for Placement::place_all to find their bind positions over
  // the pool: the same positions and the same log at one thread and at three.
  CactusOptions big;
  big.target_triangles = 200000;
  const Model model = make_cactus(big);
  int node = -1;
  for (std::size_t n = 0; n < model.nodes.size(); ++n)
    if (model.nodes[n].mesh == 0) node = static_cast<int>(n);
  ASSERT_GE(node, 0);
  const int skin = model.nodes[static_cast<std::size_t>(node)].skin;
  ASSERT_GE(skin, 0);
  const auto world = world_matrices(model, sample_pose(model, 0, 0.3f * model.animations[0].duration()));
  const SurfaceMesh input = model.meshes[0].primitives[0].mesh;
  PosedMesh posed;
  posed.posed = posed_positions(model, node, input, world);
  for (const glm::vec3& p : posed.posed) posed.bounds.add(p);
  posed.joints = joint_matrices(model, skin, world);
  posed.world = world[static_cast<std::size_t>(node)];
  posed.gridless = true;
  const Plane plane{{0.3f, 6.0f, 0.0f}, {0.3f, 1.0f, 0.2f}};
  const std::size_t saved = thread_count();
  SurfaceMesh mesh[2] = {input, input};
  CutResult r[2];
  for (int i = 0; i < 2; ++i) {
    set_thread_count(i == 0 ? 1 : 3);
    PosedMesh fresh = posed;  // the cut appends the posed crossings to it
    r[i] = cut_mesh(mesh[i], fresh, plane);
  }
  set_thread_count(saved);
  ASSERT_EQ(r[0].status, OpStatus::Ok);
  std::size_t moved = 0;  // crossings placed off their interpolated bind positions
  for (const Edit& e : r[0].log.edits)
    if (const auto* m = std::get_if<VertexMoved>(&e); m != nullptr && m->v.index >= input.vertex_count())
      ++moved;
  EXPECT_GE(moved, 256u);
  EXPECT_EQ(mesh[1].positions(), mesh[0].positions());
  EXPECT_EQ(mesh[1].faces(), mesh[0].faces());
  EXPECT_EQ(r[1].pieces, r[0].pieces);
  expect_same_log(r[1].log, r[0].log);
}

TEST(CutTest, keeping_one_side_does_not_depend_on_the_thread_count) {
  // Two scan chunks or more at two threads (2 x kMinPassGrain faces and more): the dropped side's
  // faces (or, keeping both, each side's) are joined chunk by chunk (live_side_faces).
  const SurfaceMesh input = test::make_grid(260, 140);
  ASSERT_GE(input.face_count(), 2 * detail::kMinPassGrain);
  const Plane plane{{0.5f, 0.5f, 0.0f}, {1.0f, 0.37f, 0.0f}};
  const std::size_t saved = thread_count();
  const std::size_t threads[] = {1, 2, 3, 16};
  constexpr std::size_t kRuns = std::size(threads);
  for (CutKeep keep : {CutKeep::Positive, CutKeep::Negative, CutKeep::Both}) {
    SCOPED_TRACE(static_cast<int>(keep));
    CutOptions options;
    options.keep = keep;
    SurfaceMesh mesh[kRuns] = {input, input, input, input};
    CutResult r[kRuns];
    for (std::size_t i = 0; i < kRuns; ++i) {
      set_thread_count(threads[i]);
      r[i] = cut_mesh(mesh[i], mesh[i].positions(), plane, options);
    }
    set_thread_count(saved);
    ASSERT_EQ(r[0].status, OpStatus::Ok);
    if (keep == CutKeep::Both) {
      ASSERT_EQ(r[0].pieces.size(), 2u);
    } else {
      ASSERT_EQ(r[0].pieces.size(), 1u);
      EXPECT_LT(r[0].pieces[0].size(), input.face_count());  // a side dropped
    }
    for (std::size_t i = 1; i < kRuns; ++i) {
      SCOPED_TRACE(threads[i]);
      EXPECT_EQ(mesh[i].faces(), mesh[0].faces());
      EXPECT_EQ(mesh[i].positions(), mesh[0].positions());
      std::vector<bool> dropped[2];
      for (int m = 0; m < 2; ++m)
        for (std::size_t f = 0; f < mesh[0].face_slots(); ++f)
          dropped[m].push_back(mesh[m == 0 ? 0 : i].is_deleted(FaceId(std::uint32_t(f))));
      EXPECT_EQ(dropped[1], dropped[0]);
      EXPECT_EQ(r[i].pieces, r[0].pieces);
      expect_same_log(r[i].log, r[0].log);
    }
  }
}

TEST(CutTest, a_vertex_no_face_uses_in_a_big_mesh_does_not_depend_on_the_thread_count) {
  // More vertices than the used-vertex flags' smallest part (8 x kMinPassGrain), so clearing and
  // checking them split over the pool; one vertex, the last, no face uses, so the vertices are
  // classified and the faces scanned again. The same result at 1, 2 and 16 threads, and the
  // grid's own cut (the stray vertex comes after the grid's, so every id is the same).
  const SurfaceMesh grid = test::make_grid(560, 560);
  ASSERT_GT(grid.vertex_count(), 8 * detail::kMinPassGrain);
  const Plane plane{{0.53f, 0.5f, 0.0f}, {1.0f, 0.21f, 0.0f}};
  const std::size_t saved = thread_count();
  SurfaceMesh plain = grid;
  set_thread_count(1);
  const CutResult a = cut_mesh(plain, plain.positions(), plane);
  const std::size_t threads[] = {1, 2, 16};
  constexpr std::size_t kRuns = std::size(threads);
  SurfaceMesh mesh[kRuns] = {grid, grid, grid};
  CutResult r[kRuns];
  for (std::size_t i = 0; i < kRuns; ++i) {
    mesh[i].add_vertex({9.0f, -7.0f, 2.0f});  // about 10 units off: a wider tolerance until redone
    set_thread_count(threads[i]);
    r[i] = cut_mesh(mesh[i], mesh[i].positions(), plane);
  }
  set_thread_count(saved);
  ASSERT_EQ(a.status, OpStatus::Ok);
  ASSERT_EQ(r[0].status, OpStatus::Ok);
  EXPECT_EQ(r[0].pieces, a.pieces);
  EXPECT_EQ(mesh[0].face_slots(), plain.face_slots());
  for (std::size_t i = 1; i < kRuns; ++i) {
    SCOPED_TRACE(threads[i]);
    EXPECT_EQ(mesh[i].faces(), mesh[0].faces());
    EXPECT_EQ(mesh[i].positions(), mesh[0].positions());
    EXPECT_EQ(r[i].pieces, r[0].pieces);
    EXPECT_EQ(r[i].rim_vertices, r[0].rim_vertices);
    expect_same_log(r[i].log, r[0].log);
  }
}

}  // namespace deepcut
