// SPDX-License-Identifier: MIT
#include "deepcut/core/surface_mesh.h"

#include <gtest/gtest.h>

#include <string>

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

TEST(SurfaceMeshTest, add_faces_rejects_a_batch_naming_its_first_bad_face) {
  SurfaceMesh mesh = test::make_grid(1, 1);  // 4 vertices, 2 faces
  const std::size_t corners = mesh.corner_attrs().size();
  const Triangle faces[4] = {{VertexId(0), VertexId(1), VertexId(2)},
                             {VertexId(1), VertexId(7), VertexId(2)},
                             {VertexId(9), VertexId(1), VertexId(2)},
                             {VertexId(0), VertexId(2), VertexId(3)}};
  try {
    mesh.add_faces(faces, 4);
    ADD_FAILURE() << "a face past the vertices was added";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("(1,7,2 of 4 vertices)"), std::string::npos) << e.what();
  }
  // Refused before any change; a good batch is added whole, with a default per corner.
  EXPECT_EQ(mesh.face_slots(), 2u);
  EXPECT_EQ(mesh.corner_attrs().size(), corners);
  EXPECT_EQ(mesh.add_faces(faces + 3, 1), FaceId(2));
  EXPECT_EQ(mesh.face_slots(), 3u);
  EXPECT_EQ(mesh.corner_attrs().size(), corners + 3);
  EXPECT_EQ(mesh.add_faces(faces, 0), FaceId(3));
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
