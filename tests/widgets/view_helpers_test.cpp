// SPDX-License-Identifier: MIT
// The studio's VTK-side helpers without rendering: re-posing a bridged poly data, colour
// arrays, the material look from passthrough JSON, textures from glTF images, overlay props.
#include <gtest/gtest.h>
#include <vtkActor.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMapper.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkTexture.h>
#include <vtkUnsignedCharArray.h>

#include <fstream>
#include <iterator>

#include "deepcut/core/attributes.h"
#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/widgets/material_look.h"
#include "deepcut/widgets/overlay_props.h"
#include "deepcut/widgets/poly_data_bridge.h"
#include "deepcut/widgets/texture.h"
#include "fixtures.h"

namespace deepcut {
namespace {

TEST(ViewHelpersTest, update_points_moves_every_split_point_with_its_vertex) {
  const SurfaceMesh mesh = test::make_grid(3, 3);  // UV seam: some vertices have two points
  auto poly = to_poly_data(mesh);
  ASSERT_GT(poly->GetNumberOfPoints(), static_cast<vtkIdType>(mesh.vertex_count()));
  ASSERT_NE(poly->GetPointData()->GetArray("corner_id"), nullptr);
  std::vector<glm::vec3> moved = mesh.positions();
  for (glm::vec3& p : moved) p = p * 2.0f + glm::vec3(1.0f, 0.0f, 3.0f);
  update_poly_data_points(poly, moved);
  vtkDataArray* ids = poly->GetPointData()->GetArray("vertex_id");
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) {
    double p[3];
    poly->GetPoint(i, p);
    const glm::vec3& expected = moved[static_cast<std::size_t>(ids->GetTuple1(i))];
    EXPECT_NEAR(p[0], expected.x, 1e-6);
    EXPECT_NEAR(p[1], expected.y, 1e-6);
    EXPECT_NEAR(p[2], expected.z, 1e-6);
  }
  EXPECT_THROW(update_poly_data_points(poly, std::vector<glm::vec3>(2)), Error);
}

TEST(ViewHelpersTest, update_points_sets_corner_normals) {
  SurfaceMesh mesh = test::make_tube(8, 2);
  mesh.corner_attrs().add<glm::vec3>(attr::kNormal, glm::vec3(1.0f, 0.0f, 0.0f));
  auto poly = to_poly_data(mesh);
  ASSERT_NE(poly->GetPointData()->GetNormals(), nullptr);
  std::vector<glm::vec3> normals(3 * mesh.face_slots(), glm::vec3(0.0f, 0.0f, 1.0f));
  update_poly_data_points(poly, mesh.positions(), &normals);
  vtkDataArray* n = poly->GetPointData()->GetNormals();
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) EXPECT_DOUBLE_EQ(n->GetComponent(i, 2), 1.0);
}

TEST(ViewHelpersTest, vertex_and_face_colours_become_active_scalars) {
  const SurfaceMesh mesh = test::make_grid(2, 2);
  auto poly = to_poly_data(mesh);
  std::vector<glm::u8vec3> vertex_colors(mesh.vertex_count());
  for (std::size_t v = 0; v < vertex_colors.size(); ++v) vertex_colors[v] = glm::u8vec3(v, 2 * v, 3 * v);
  set_vertex_colors(poly, vertex_colors);
  auto* colors = vtkUnsignedCharArray::SafeDownCast(poly->GetPointData()->GetScalars());
  ASSERT_NE(colors, nullptr);
  vtkDataArray* ids = poly->GetPointData()->GetArray("vertex_id");
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) {
    const auto v = static_cast<unsigned>(ids->GetTuple1(i));
    EXPECT_EQ(colors->GetTypedComponent(i, 1), 2 * v);
  }
  set_face_colors(poly, std::vector<glm::u8vec3>(mesh.face_slots(), glm::u8vec3(9, 8, 7)));
  EXPECT_EQ(poly->GetPointData()->GetArray("colors"), nullptr) << "one colouring at a time";
  ASSERT_NE(poly->GetCellData()->GetScalars(), nullptr);
  EXPECT_EQ(poly->GetCellData()->GetScalars()->GetComponent(0, 0), 9.0);
  clear_colors(poly);
  EXPECT_EQ(poly->GetCellData()->GetArray("colors"), nullptr);
  EXPECT_THROW(set_face_colors(poly, std::vector<glm::u8vec3>(1)), Error);
}

TEST(ViewHelpersTest, material_look_reads_base_colour_and_texture) {
  const Model cesium = read_gltf(DEEPCUT_ASSETS_DIR "/models/CesiumMan/CesiumMan.glb");
  const MaterialLook look = material_look(cesium, cesium.meshes[0].primitives[0].material);
  ASSERT_GE(look.base_color_image, 0);
  EXPECT_EQ(look.texcoord, 0);
  const Model tube = test::make_skinned_tube_model();
  const MaterialLook red = material_look(tube, 0);
  EXPECT_EQ(red.base_color, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
  EXPECT_EQ(red.base_color_image, -1);
  EXPECT_EQ(material_look(tube, -1).base_color, MaterialLook().base_color);
  EXPECT_EQ(material_look(tube, 7).base_color, MaterialLook().base_color);
  Model broken = tube;
  broken.materials[0].json = "{not json";
  EXPECT_EQ(material_look(broken, 0).base_color, glm::vec4(1.0f)) << "malformed JSON: glTF defaults";
}

TEST(ViewHelpersTest, textures_decode_png_and_jpeg_and_refuse_other_bytes) {
  for (const char* path :
       {DEEPCUT_ASSETS_DIR "/models/CesiumMan/CesiumMan.glb", DEEPCUT_ASSETS_DIR "/models/Fox/Fox.glb"}) {
    const Model model = read_gltf(path);
    ASSERT_FALSE(model.images.empty()) << path;
    const auto texture = make_texture(model.images[0]);
    ASSERT_NE(texture, nullptr);
    int dims[3];
    vtkImageData::SafeDownCast(texture->GetInputDataObject(0, 0))->GetDimensions(dims);
    EXPECT_GT(dims[0], 16) << path;
    EXPECT_GT(dims[1], 16) << path;
  }
  Image garbage;
  garbage.name = "noise";
  garbage.data = {1, 2, 3, 4, 5, 6, 7, 8};
  EXPECT_THROW(make_texture(garbage), Error);
  Image truncated;
  truncated.name = "cut";
  truncated.data = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A, 0, 0, 0};
  try {
    make_texture(truncated);
    FAIL() << "a truncated PNG decoded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'cut'"), std::string::npos) << e.what();
  }
}

TEST(ViewHelpersTest, overlay_props_split_depth_tested_and_on_top_sets) {
  Overlay overlay;
  OverlayPoints points;
  points.positions = {{0, 0, 0}, {1, 0, 0}};
  points.on_top = true;
  overlay.points.push_back(points);
  OverlayLines lines;
  lines.endpoints = {{0, 0, 0}, {0, 1, 0}, {0, 1, 0}, {1, 1, 0}};
  overlay.lines.push_back(lines);
  OverlaySpheres spheres;
  spheres.centers = {{0, 0, 0}};
  spheres.radii = {0.5f};
  overlay.spheres.push_back(spheres);
  overlay.points.push_back(OverlayPoints{});  // empty sets draw nothing
  const OverlayProps props = make_overlay_props(overlay);
  EXPECT_EQ(props.on_top.size(), 1u);
  ASSERT_EQ(props.depth_tested.size(), 2u);
  auto* line_actor = vtkActor::SafeDownCast(props.depth_tested[0]);
  ASSERT_NE(line_actor, nullptr);
  EXPECT_EQ(vtkPolyData::SafeDownCast(line_actor->GetMapper()->GetInputDataObject(0, 0))->GetNumberOfLines(),
            2);
  EXPECT_NE(make_color_bar(ColorBar{"w", {{0, 0, 1}, {1, 0, 0}}, 0.0f, 1.0f}), nullptr);
}

}  // namespace
}  // namespace deepcut
