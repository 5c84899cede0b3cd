// SPDX-License-Identifier: MIT
// An undo record (model_undo.h) following a primitive the mesh surgery takes apart in place
// (split_disjoint): pieces destroyed without ever entering the model still give the primitive
// back, byte for byte, on undo.
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
SurfaceMesh two_tubes() {
  const SurfaceMesh tube = test::make_tube(16, 12);
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

void expect_same(const Model& a, const Model& b, const char* when) {
  ASSERT_TRUE(same_structure(a, b)) << when;
  EXPECT_TRUE(diff_models(a, b).empty()) << when;
}

TEST(ModelUndoSplitTest, pieces_destroyed_without_entering_the_model_give_the_primitive_back_on_undo) {
  Model model;
  Primitive prim;
  prim.mesh = two_tubes();
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

}  // namespace
}  // namespace deepcut
