// SPDX-License-Identifier: MIT
#include "deepcut/core/weld.h"

#include <gtest/gtest.h>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/parallel.h"
#include "fixtures.h"

namespace deepcut {
namespace {

// Every corner its own vertex, as a non-indexed glTF primitive stores it.
SurfaceMesh unweld(const SurfaceMesh& mesh) {
  SurfaceMesh out;
  auto& j = out.vertex_attrs().add<glm::u16vec4>(attr::kJoints0);
  auto& w = out.vertex_attrs().add<glm::vec4>(attr::kWeights0);
  auto& uv = out.corner_attrs().add<glm::vec2>(attr::kUv0);
  const auto& sj = mesh.vertex_attrs().get<glm::u16vec4>(attr::kJoints0);
  const auto& sw = mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0);
  const auto& suv = mesh.corner_attrs().get<glm::vec2>(attr::kUv0);
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    VertexId v[3];
    for (int k = 0; k < 3; ++k) {
      v[k] = out.add_vertex(mesh.position(t[k]));
      j[v[k].index] = sj[t[k].index];
      w[v[k].index] = sw[t[k].index];
    }
    const FaceId g = out.add_face(v[0], v[1], v[2]);
    for (int k = 0; k < 3; ++k) uv[SurfaceMesh::corner(g, k)] = suv[SurfaceMesh::corner(f, k)];
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

TEST(WeldTest, the_result_does_not_depend_on_the_thread_count) {
  // Large enough for several parallel chunks.
  const SurfaceMesh split = unweld(test::make_grid(160, 120));
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

}  // namespace deepcut
