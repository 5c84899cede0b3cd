// SPDX-License-Identifier: MIT
// ViewPolyData of a cut's piece built through the piece's origin (ModelChange::origins: how its
// corners share points taken from the data drawn for the primitive it was cut out of) equals a
// fresh build of the piece: at rest and skinned, with uv seams, corner normals and morph targets,
// and from source data whose points were renumbered by earlier steps. Headless: VTK data only.

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/model_undo.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/widgets/view_poly_data.h"
#include "fixtures.h"
#include "view_checks.h"

namespace deepcut {
namespace {

/// The grid (uv seam down its middle column) as a one-node model, standing up in the xz plane.
Model grid_model(int nx, int ny) {
  Model model;
  Primitive prim;
  prim.mesh = test::make_grid(nx, ny);
  for (auto& p : prim.mesh.vertex_attrs().get<glm::vec3>(attr::kPosition).data()) p = glm::vec3(p.x, 0.0f, p.y);
  Mesh mesh;
  mesh.primitives.push_back(std::move(prim));
  model.meshes.push_back(std::move(mesh));
  Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  model.scenes.push_back({0});
  model.default_scene = 0;
  return model;
}

/// The drawn data of one instance at one pose: its posed positions and corner normals.
struct Drawn {
  const SurfaceMesh* mesh = nullptr;
  std::vector<glm::vec3> positions, normals;
};

Drawn drawn(const Model& model, const PosedModel& posed, int node, int mesh, int primitive) {
  Drawn out;
  out.mesh = &model.meshes[static_cast<std::size_t>(mesh)].primitives[static_cast<std::size_t>(primitive)].mesh;
  const PosedMesh* pose = posed.find(node, primitive);
  EXPECT_NE(pose, nullptr);
  if (!pose) return out;
  out.positions = pose->posed;
  out.normals = pose->corner_normals(*out.mesh);
  return out;
}

/// `view` (drawing `d`) follows a step that deletes every third face, then one that brings them
/// back: its points are then numbered otherwise than a fresh build's.
void renumber_points(ViewPolyData& view, const Drawn& d, const std::string& what) {
  SurfaceMesh fewer = *d.mesh;
  MeshEditor editor(fewer);
  for (std::uint32_t f = 0; f < fewer.face_slots(); f += 3)
    if (!fewer.is_deleted(FaceId(f))) editor.remove_face(FaceId(f));
  PrimitiveChange change;
  ASSERT_TRUE(diff_meshes(*d.mesh, fewer, change));
  view.update(fewer, d.positions, &d.normals, change);
  expect_rebuilt(view, fewer, d.positions, &d.normals, what + " (faces deleted)");
  ASSERT_TRUE(diff_meshes(fewer, *d.mesh, change));
  view.update(*d.mesh, d.positions, &d.normals, change);
  expect_rebuilt(view, *d.mesh, d.positions, &d.normals, what);
}

/// Cuts `model` by `plane` at (`animation`, `time`) under an undo record (as the studio's session
/// does, so the cut says where its pieces came from), then checks every piece's data built
/// through its origin against a fresh build. With `renumber` the source's data first follows a
/// step that deletes some faces and one that brings them back, so its points are numbered
/// otherwise than a fresh build's.
void check_pieces(Model model, const Plane& plane, int animation, float time, bool renumber, const std::string& what) {
  SCOPED_TRACE(what);
  const Model before = model;
  Operation op;
  op.params = CutOperation{};
  std::get<CutOperation>(op.params).plane = plane;
  op.animation = animation;
  op.time = time;
  PosedModel posed;
  OperationResult result;
  {
    ModelRecorder recorder(model);
    result = apply_operation(model, op, posed);
    recorder.finish();
  }
  ASSERT_EQ(result.status, OpStatus::Ok);
  const auto& origins = std::get<ModelCutResult>(result.result).origins;
  ASSERT_FALSE(origins.empty());
  const PosedModel posed_before = PosedModel::build(before, animation, time, PoseDetail::Positions);
  const PosedModel posed_after = PosedModel::build(model, animation, time, PoseDetail::Positions);
  for (const auto& origin : origins) {
    const Drawn source = drawn(before, posed_before, origin->node_before, origin->mesh_before, origin->primitive_before);
    const Drawn piece = drawn(model, posed_after, origin->node, origin->mesh, origin->primitive);
    ASSERT_TRUE(source.mesh && piece.mesh);
    ASSERT_EQ(origin->faces.size(), piece.mesh->face_slots());
    ASSERT_EQ(origin->vertices.size(), piece.mesh->vertex_count());
    ViewPolyData source_view(*source.mesh, source.positions, &source.normals);
    if (renumber) renumber_points(source_view, source, "the source renumbered");
    ViewPolyData copied(*piece.mesh, piece.positions, &piece.normals, source_view, *origin);
    const std::string name = "piece of node " + std::to_string(origin->node);
    expect_rebuilt(copied, *piece.mesh, piece.positions, &piece.normals, name);
    // Its first update builds the corner lists the copy left out.
    renumber_points(copied, piece, name + ", then updated");
  }
}
Plane plane_through(const glm::vec3& point, const glm::vec3& normal) {
  Plane plane;
  plane.point = point;
  plane.normal = normal;
  return plane;
}

TEST(ViewPolyDataOriginTest, uv_seams_at_rest) {
  const Plane plane = plane_through({0.37f, 0.0f, 0.41f}, {0.3f, 0.0f, 1.0f});
  check_pieces(grid_model(12, 9), plane, -1, 0.0f, false, "fresh source");
  check_pieces(grid_model(12, 9), plane, -1, 0.0f, true, "renumbered source");
}

TEST(ViewPolyDataOriginTest, skinned_with_corner_normals) {
  const Plane plane = plane_through({0.0f, 1.3f, 0.0f}, {0.15f, 1.0f, 0.05f});
  check_pieces(test::make_skinned_tube_model(), plane, -1, 0.0f, false, "at rest");
  check_pieces(test::make_skinned_tube_model(), plane, 0, 0.5f, true, "bent");
}

TEST(ViewPolyDataOriginTest, morph_targets_skinned) {
  const Plane plane = plane_through({0.0f, 1.8f, 0.0f}, {-0.1f, 1.0f, 0.2f});
  check_pieces(test::make_morph_tube_model(), plane, -1, 0.0f, false, "at rest");
  check_pieces(test::make_morph_tube_model(), plane, 0, 1.0f, true, "bent and morphed");
}

}  // namespace
}  // namespace deepcut
