// SPDX-License-Identifier: MIT
// An undo record (model_undo.h) following a primitive the mesh surgery takes apart in place
// (split_disjoint): pieces destroyed without ever entering the model still give the primitive
// back, byte for byte, on undo, whatever attributes the primitive carries.
#include <gtest/gtest.h>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/model_change.h"
#include "deepcut/core/model_undo.h"
#include "fixtures.h"
#include "ops/common/model_surgery.h"

namespace deepcut {
namespace {

// Two tubes side by side in one mesh (no shared vertex), an unused vertex after them and the
// first face deleted: the split's pieces are the tubes, the rest the unused vertex and the face.
SurfaceMesh two_tubes(int around = 16, int along = 12) {
  const SurfaceMesh tube = test::make_tube(around, along);
  const std::size_t nv = tube.vertex_count(), nf = tube.face_slots();
  AttributeSet v = tube.vertex_attrs(), f = tube.face_attrs(), c = tube.corner_attrs();
  v.append_from(tube.vertex_attrs(), 0, nv);
  v.append_from(tube.vertex_attrs(), 0, 1);
  f.append_from(tube.face_attrs(), 0, nf);
  c.append_from(tube.corner_attrs(), 0, 3 * nf);
  std::vector<Triangle> tris = tube.faces();
  for (std::size_t i = 0; i < nf; ++i) {
    Triangle t = tube.faces()[i];
    for (VertexId& x : t) x = VertexId(x.index + static_cast<std::uint32_t>(nv));
    tris.push_back(t);
  }
  SurfaceMesh mesh;
  mesh.assign(std::move(tris), std::move(v), std::move(f), std::move(c));
  MeshEditor(mesh).remove_face(FaceId(0));
  return mesh;
}

// `mesh` with an 8-slot skin (JOINTS_0/1, WEIGHTS_0/1), u8 and u32 face attributes and attributes
// whose default is not zero (a face's and a corner's), every element a value of its own.
SurfaceMesh with_attribute_kinds(SurfaceMesh mesh) {
  AttributeSet &v = mesh.vertex_attrs(), &f = mesh.face_attrs(), &c = mesh.corner_attrs();
  auto& j0 = v.add<glm::u16vec4>(attr::kJoints0);
  auto& j1 = v.add<glm::u16vec4>(attr::kJoints1);
  auto& w0 = v.add<glm::vec4>(attr::kWeights0);
  auto& w1 = v.add<glm::vec4>(attr::kWeights1, glm::vec4(0.25f));
  auto& f8 = f.add<std::uint8_t>("f:u8");
  auto& f32 = f.add<std::uint32_t>("f:u32", 7u);
  auto& cs = c.add<float>("c:scale", 1.5f);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto k = static_cast<std::uint16_t>(i);
    j0[i] = glm::u16vec4(k, k + 1, k + 2, k + 3);
    j1[i] = glm::u16vec4(k + 4, k + 5, k + 6, k + 7);
    w0[i] = glm::vec4(0.5f, 0.2f, 0.1f, 0.05f) + static_cast<float>(i) * 1e-4f;
    if (i % 3) w1[i] = glm::vec4(0.05f, 0.04f, 0.03f, 0.03f);
  }
  for (std::size_t i = 0; i < f.size(); ++i) {
    f8[i] = static_cast<std::uint8_t>(i * 37);
    if (i % 4) f32[i] = static_cast<std::uint32_t>(i * 2654435761u);
  }
  for (std::size_t i = 0; i < c.size(); ++i)
    if (i % 5) cs[i] = static_cast<float>(i) * 0.5f;
  return mesh;
}

void expect_same(const Model& a, const Model& b, const char* when) {
  ASSERT_TRUE(same_structure(a, b)) << when;
  EXPECT_TRUE(diff_models(a, b).empty()) << when;
}

// Records an edit of `mesh`'s primitive and its split in place into the tubes; the pieces are
// destroyed without entering the model. The step is exact; undo and redo give back the states.
void expect_pieces_destroyed_undone(SurfaceMesh source) {
  Model model;
  Primitive prim;
  prim.mesh = std::move(source);
  model.meshes.push_back({"tubes", {prim}, ""});
  Node node;
  node.mesh = 0;
  model.nodes = {node};
  model.scenes = {{0}};
  const Model before = model;
  const std::uint32_t half = static_cast<std::uint32_t>(model.meshes[0].primitives[0].mesh.face_slots() / 2);

  ModelStep step;
  {
    ModelRecorder recorder(model);
    SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
    MeshEditor(mesh).remove_face(FaceId(half + 5));  // an edit recorded before the split
    std::vector<std::vector<FaceId>> lists(2);
    for (std::uint32_t f = 0; f < mesh.face_slots(); ++f)
      if (!mesh.is_deleted(FaceId(f))) lists[f < half ? 0 : 1].push_back(FaceId(f));
    const void* positions = mesh.vertex_attrs().base(attr::kPosition)->element_data(0);
    {
      const std::vector<SurfaceMesh> pieces = detail::split_disjoint(std::move(mesh), lists);
      ASSERT_EQ(pieces.size(), 2u);
      // Taken apart in place: a piece keeps the primitive's arrays.
      bool in_place = false;
      for (const SurfaceMesh& p : pieces) in_place = in_place || p.positions().data() == positions;
      EXPECT_TRUE(in_place);
    }  // the pieces are destroyed here, never installed
    step = recorder.finish();
  }
  const Model after = model;
  ASSERT_TRUE(step.exact());
  for (int cycle = 0; cycle < 2; ++cycle) {
    step.undo(model);
    expect_same(model, before, "undo");
    step.redo(model);
    expect_same(model, after, "redo");
  }
}

TEST(ModelUndoSplitTest, pieces_destroyed_without_entering_the_model_give_the_primitive_back_on_undo) {
  expect_pieces_destroyed_undone(two_tubes());
}

// Tubes of some 10,000 faces each, with faces deleted here and there (the rest the split keeps
// lies in a few of the stretches of indices it is looked for in, the others hold none): still
// exact, byte for byte.
TEST(ModelUndoSplitTest, a_rest_spread_over_a_big_primitive_comes_back_too) {
  SurfaceMesh mesh = two_tubes(100, 50);
  ASSERT_GT(mesh.face_slots(), 16000u);
  {
    MeshEditor editor(mesh);
    for (std::uint32_t f : {4095u, 4096u, 9000u, 12289u, 16000u}) editor.remove_face(FaceId(f));
  }
  expect_pieces_destroyed_undone(std::move(mesh));
}

TEST(ModelUndoSplitTest, a_skin_of_8_slots_face_attributes_and_defaults_not_zero_come_back_too) {
  expect_pieces_destroyed_undone(with_attribute_kinds(two_tubes()));
}

}  // namespace
}  // namespace deepcut
