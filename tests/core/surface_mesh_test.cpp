// SPDX-License-Identifier: MIT
#include "deepcut/core/surface_mesh.h"

#include <gtest/gtest.h>

#include "fixtures.h"

namespace deepcut {

TEST(SurfaceMeshTest, grid_counts_area_and_attribute_sizes) {
  const SurfaceMesh mesh = test::make_grid(4, 3);
  EXPECT_EQ(mesh.vertex_count(), 20u);
  EXPECT_EQ(mesh.face_count(), 24u);
  EXPECT_EQ(mesh.corner_attrs().size(), 72u);
  EXPECT_NEAR(mesh.area(), 1.0, 1e-6);
  test::expect_valid(mesh, 2);
}

TEST(SurfaceMeshTest, closed_tube_volume_is_positive_and_near_cylinder) {
  const SurfaceMesh mesh = test::make_tube(64, 4, 1.0f, 2.0f);
  const double polygon_area = 0.5 * 64 * std::sin(2 * M_PI / 64);  // inscribed 64-gon
  EXPECT_NEAR(mesh.volume(), polygon_area * 2.0, 1e-4);
}

TEST(SurfaceMeshTest, add_face_rejects_bad_index) {
  SurfaceMesh mesh;
  mesh.add_vertex({0, 0, 0});
  EXPECT_THROW(mesh.add_face(VertexId(0), VertexId(1), VertexId(2)), Error);
}

TEST(SurfaceMeshTest, compact_drops_deleted_faces_and_unused_vertices) {
  SurfaceMesh mesh = test::make_grid(2, 1);  // 6 vertices, 4 faces
  const auto uv_before = mesh.corner_attrs().get<glm::vec2>(attr::kUv0)[SurfaceMesh::corner(FaceId(3), 1)];
  mesh.mark_deleted(FaceId(0));
  mesh.mark_deleted(FaceId(1));
  EXPECT_EQ(mesh.face_count(), 2u);
  const auto vmap = mesh.compact();
  EXPECT_EQ(mesh.face_count(), 2u);
  EXPECT_EQ(mesh.face_slots(), 2u);
  EXPECT_EQ(mesh.vertex_count(), 4u);
  EXPECT_EQ(vmap[0], kInvalidIndex);
  EXPECT_EQ(mesh.corner_attrs().get<glm::vec2>(attr::kUv0)[SurfaceMesh::corner(FaceId(1), 1)], uv_before);
  test::expect_valid(mesh, 2);
}

TEST(SurfaceMeshTest, moved_from_mesh_is_empty_and_usable) {
  SurfaceMesh a = test::make_grid(2, 2);
  SurfaceMesh b = std::move(a);
  EXPECT_EQ(b.face_count(), 8u);
  EXPECT_EQ(a.vertex_count(), 0u);  // NOLINT(bugprone-use-after-move): documented state
  a.add_vertex({1, 2, 3});
  EXPECT_EQ(a.positions()[0], glm::vec3(1, 2, 3));
}

}  // namespace deepcut
