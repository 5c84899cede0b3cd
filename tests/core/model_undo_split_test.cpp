// SPDX-License-Identifier: MIT
// An undo record (model_undo.h) following a primitive the mesh surgery takes apart in place
// (split_disjoint): pieces destroyed without ever entering the model still give the primitive
// back, byte for byte, on undo, whatever attributes the primitive carries; pieces that enter the
// model are recorded in a few bits per element (PieceLabels), and consecutive structural steps
// share the model's small parts.
#include <gtest/gtest.h>

#include <cmath>

#include "deepcut/core/errors.h"
#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/model_change.h"
#include "deepcut/core/model_undo.h"
#include "deepcut/core/parallel.h"
#include "fixtures.h"
#include "model_undo_labels.h"
#include "model_undo_parts.h"
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

// Undoes and redoes `step` twice over: `model` is `before` after each undo, `after` after each redo.
void expect_undo_redo(ModelStep& step, Model& model, const Model& before, const Model& after) {
  for (int cycle = 0; cycle < 2; ++cycle) {
    step.undo(model);
    expect_same(model, before, "undo");
    step.redo(model);
    expect_same(model, after, "redo");
  }
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
  expect_undo_redo(step, model, before, after);
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

// Labels give back the lists they were made from and the elements none holds, whatever the
// number of pieces, in the fewest bits (1, 2, 4, 8, ...) that number the pieces and the rest.
TEST(PieceLabelsTest, give_back_the_lists_in_the_fewest_bits_per_element) {
  const std::size_t count = 200000;  // several stretches of the labels' passes
  for (std::size_t pieces : {1u, 2u, 3u, 4u, 17u}) {
    std::vector<std::vector<std::uint32_t>> lists(pieces + 1);  // the rest last
    std::uint32_t x = 12345;
    for (std::uint32_t i = 0; i < count; ++i) {
      x = x * 1664525u + 1013904223u;
      lists[(x >> 8) % (pieces + 1)].push_back(i);
    }
    const std::vector<std::uint32_t> rest = lists.back();
    lists.pop_back();
    const undo::PieceLabels labels(lists, count);
    const unsigned bits = pieces == 1 ? 1 : pieces <= 3 ? 2 : pieces <= 15 ? 4 : 8;
    EXPECT_EQ(labels.bits(), bits);
    ASSERT_EQ(labels.pieces(), pieces);
    EXPECT_EQ(labels.count(), count);
    const std::vector<std::vector<std::uint32_t>> got = labels.lists();
    ASSERT_EQ(got.size(), pieces + 1);
    for (std::size_t k = 0; k < pieces; ++k) {
      EXPECT_TRUE(got[k] == lists[k]) << pieces << " pieces, piece " << k;
      EXPECT_EQ(labels.size(k), lists[k].size());
    }
    EXPECT_TRUE(got[pieces] == rest) << pieces << " pieces";
    EXPECT_TRUE(labels.list(pieces) == rest) << pieces << " pieces";
    EXPECT_TRUE(labels.list(0) == lists[0]) << pieces << " pieces";
    EXPECT_LE(labels.bytes(), count * bits / 8 + 64 * (pieces + 1) + 64) << pieces << " pieces";
  }
}

// Labels of 16 and 32 bits (hundreds and tens of thousands of pieces), with empty pieces and a
// last word only partly used, give back their lists, the same whatever the number of threads.
TEST(PieceLabelsTest, give_back_the_lists_at_every_width_and_thread_count) {
  const std::size_t threads = thread_count();
  for (std::size_t pieces : {1000u, 70000u}) {
    const std::size_t count = 3 * 65536 + 7;  // 7 labels in the last word
    std::vector<std::vector<std::uint32_t>> lists(pieces + 1);
    std::uint32_t x = 777;
    for (std::uint32_t i = 0; i < count; ++i) {
      x = x * 1664525u + 1013904223u;
      lists[1 + (x >> 4) % pieces].push_back(i);  // piece 0 empty; the rest last
    }
    const std::vector<std::uint32_t> rest = lists.back();
    lists.pop_back();
    const undo::PieceLabels labels(lists, count);
    EXPECT_EQ(labels.bits(), pieces < 65535 ? 16u : 32u);
    EXPECT_EQ(labels.size(0), 0u);
    for (std::size_t t : {std::size_t{1}, std::size_t{3}}) {
      set_thread_count(t);
      const std::vector<std::vector<std::uint32_t>> got = labels.lists();
      ASSERT_EQ(got.size(), pieces + 1);
      for (std::size_t k = 0; k < pieces; ++k)
        ASSERT_TRUE(got[k] == lists[k]) << pieces << " pieces, piece " << k;
      EXPECT_TRUE(got[pieces] == rest) << pieces << " pieces, " << t << " threads";
    }
    set_thread_count(threads);
  }
}

// Lists that are not increasing, reach past the count or share an element are refused.
TEST(PieceLabelsTest, refuse_lists_not_increasing_or_overlapping) {
  using Lists = std::vector<std::vector<std::uint32_t>>;
  EXPECT_THROW(undo::PieceLabels(Lists{{3, 1}}, 10), Error);
  EXPECT_THROW(undo::PieceLabels(Lists{{1, 1}}, 10), Error);
  EXPECT_THROW(undo::PieceLabels(Lists{{1, 10}}, 10), Error);
  EXPECT_THROW(undo::PieceLabels(Lists{{1, 2}, {2, 3}}, 10), Error);
  EXPECT_NO_THROW(undo::PieceLabels(Lists{{1, 2}, {}, {3}}, 10));
}

std::vector<std::uint32_t> range(std::uint32_t b, std::uint32_t e) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t i = b; i < e; ++i) out.push_back(i);
  return out;
}

// The slots of the rest the step's delta gives back (here all of it) need room when the primitive
// grows back: no other piece holds as many vertices and as many faces (one has the faces, the
// other the vertices), so the room is made of both, and the rooms add up to the growth (the
// arrays grow by copies, not by a fill of default values).
TEST(ModelUndoSplitTest, the_room_a_primitive_grows_back_into_adds_up_from_several_pieces) {
  const SurfaceMesh mesh = two_tubes();  // holds more than the 100 elements labelled
  undo::SplitPart part;
  part.vertices = undo::PieceLabels({range(0, 40), range(40, 45), range(45, 80)}, 100);
  part.faces = undo::PieceLabels({range(0, 40), range(40, 80), range(80, 85)}, 100);
  part.big = 0;
  undo::MeshDelta at_split;
  at_split.v0 = at_split.f0 = at_split.v1 = at_split.f1 = 100;
  at_split.vertices = range(80, 100);  // the rest's vertices, all rewritten by the step
  at_split.faces = range(85, 100);
  part.take_rest(mesh, at_split);
  EXPECT_TRUE(part.rest_vertices.empty() && part.rest_faces.empty());
  const std::vector<const SurfaceMesh*> pieces(3, &mesh);
  const std::vector<detail::Room> rooms = undo::rooms_to_grow(part, pieces, part.lists());
  std::size_t vertices = 0, faces = 0;
  for (const detail::Room& room : rooms) {
    vertices += room.vertices;
    faces += room.faces;
  }
  EXPECT_EQ(vertices, 60u);
  EXPECT_EQ(faces, 60u);
}

Model model_of(SurfaceMesh mesh) {
  Model model;
  Primitive prim;
  prim.mesh = std::move(mesh);
  model.meshes.push_back({"tubes", {prim}, ""});
  Node node;
  node.mesh = 0;
  model.nodes = {node};
  model.scenes = {{0}};
  return model;
}

// An animation of `keys` keys on node 0: 16 bytes a key.
Animation long_animation(std::size_t keys) {
  Animation a;
  a.name = "sway";
  AnimationSampler s;
  for (std::size_t i = 0; i < keys; ++i) {
    s.input.push_back(static_cast<float>(i) * 0.01f);
    for (int c = 0; c < 3; ++c)
      s.output.push_back(static_cast<float>(i % 97) * 0.001f * static_cast<float>(c + 1));
  }
  a.samplers.push_back(std::move(s));
  a.channels.push_back({0, 0, AnimationPath::Translation});
  return a;
}

// Splits the model's first primitive in place into its tubes, which take its place and a new
// primitive's, after edits the step's delta gives back itself: a face deleted, the unused
// vertex moved, a face appended and deleted (slots no piece holds whose values the rest need not
// keep). `history`, when given, is written as the root extras within the recording (as the
// session writes its history). `last`: the structural step made before. Returns the step.
ModelStep split_into_the_model(Model& model, const char* history = nullptr, const ModelStep* last = nullptr) {
  ModelRecorder recorder(model);
  if (history) model.extras_json = history;
  SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  const auto half = static_cast<std::uint32_t>(mesh.face_slots() / 2);
  {
    MeshEditor editor(mesh);
    editor.remove_face(FaceId(half + 5));
    editor.move_vertex(VertexId(static_cast<std::uint32_t>(mesh.vertex_count() - 1)), glm::vec3(7.0f));
    const Triangle copy = mesh.face(FaceId(half + 6));  // a copy: adding a face may move the faces
    editor.remove_face(editor.add_face(copy));
  }
  std::vector<std::vector<FaceId>> lists(2);
  for (std::uint32_t f = 0; f < mesh.face_slots(); ++f)
    if (!mesh.is_deleted(FaceId(f))) lists[f < half ? 0 : 1].push_back(FaceId(f));
  std::vector<SurfaceMesh> pieces = detail::split_disjoint(std::move(mesh), lists);
  EXPECT_EQ(pieces.size(), 2u);
  model.meshes[0].primitives[0].mesh = std::move(pieces[0]);
  Primitive second;
  second.mesh = std::move(pieces[1]);
  model.meshes[0].primitives.push_back(std::move(second));
  return recorder.finish(last);
}

// A split whose pieces enter the model is recorded as a label of 2 bits per element and the few
// slots no piece holds (not the pieces' index lists, 4 bytes per element): the record stays
// under half a byte per element of the primitive, and undo and redo give back both states byte
// for byte.
TEST(ModelUndoSplitTest, a_split_whose_pieces_enter_the_model_is_recorded_in_a_few_bits_per_element) {
  Model model = model_of(two_tubes(200, 100));  // big enough that the record's fixed bytes are small
  const SurfaceMesh& source = model.meshes[0].primitives[0].mesh;
  const std::size_t elements = source.vertex_count() + source.face_slots();
  ASSERT_GT(elements, 100000u);
  const Model before = model;
  ModelStep step = split_into_the_model(model);
  const Model after = model;
  ASSERT_TRUE(step.exact());
  ASSERT_EQ(model.meshes[0].primitives.size(), 2u);
  EXPECT_LT(step.bytes(), elements / 2);
  expect_undo_redo(step, model, before, after);
}

// Two structural steps in a row keep one copy of the model's small parts they did not change (a
// long animation here) when the second is told the first (ModelRecorder::finish): each step
// holds a share of it, not a copy before and after. Steps not told share nothing. Undo and redo
// of both give back every state, root extras (written within each recording, a text delta
// applied to the text as the step left it) included.
TEST(ModelUndoSplitTest, consecutive_structural_steps_share_the_small_parts_they_did_not_change) {
  const std::size_t animation_bytes = 50000 * 16;
  for (const bool told : {true, false}) {
    Model model = model_of(two_tubes());
    model.animations.push_back(long_animation(50000));
    model.extras_json = R"({"history":[]})";
    const Model before = model;
    ModelStep first = split_into_the_model(model, R"({"history":["split"]})");
    const Model middle = model;
    ModelStep second;
    {
      ModelRecorder recorder(model);
      model.extras_json = R"({"history":["split","add"]})";
      model.meshes.push_back({"more", {Primitive{}}, ""});
      second = recorder.finish(told ? &first : nullptr);
    }
    const Model after = model;
    ASSERT_TRUE(first.exact() && second.exact());
    if (told) {
      EXPECT_LT(first.bytes() + second.bytes(), animation_bytes * 3 / 2);
    } else {
      EXPECT_GT(first.bytes() + second.bytes(), animation_bytes * 19 / 10);
    }
    auto expect_state = [&](const Model& state, const char* when) {
      expect_same(model, state, when);
      EXPECT_EQ(model.extras_json, state.extras_json) << when;
    };
    for (int cycle = 0; cycle < 2; ++cycle) {
      second.undo(model);
      expect_state(middle, "undo the second");
      first.undo(model);
      expect_state(before, "undo the first");
      first.redo(model);
      expect_state(middle, "redo the first");
      second.redo(model);
      expect_state(after, "redo both");
    }
  }
}

// A replace() step holds the model it replaced, counted once: its bytes are about the model's.
TEST(ModelUndoSplitTest, a_replace_step_counts_the_model_it_holds_once) {
  Model model = model_of(two_tubes(100, 50));
  std::size_t mesh_bytes = 0;
  for (const Mesh& m : model.meshes)
    for (const Primitive& p : m.primitives) mesh_bytes += p.mesh.capacity_bytes();
  ASSERT_GT(mesh_bytes, 100000u);
  Model state = model;
  ModelStep step = ModelStep::replace(model, std::move(state));
  EXPECT_GE(step.bytes(), mesh_bytes);
  EXPECT_LT(step.bytes(), mesh_bytes + mesh_bytes / 10);
}

// A step that turns a node's rotation from +0.0 into -0.0 changes the model's bytes: it is a
// structural step (the floats are compared bit for bit), and undo and redo give back each sign,
// whether the step changes nothing else or also adds a mesh (its shells then hold both signs).
TEST(ModelUndoSplitTest, a_rotation_turned_to_minus_zero_comes_back_with_its_sign) {
  for (const bool add_mesh : {false, true}) {
    Model model = model_of(two_tubes());
    const Model before = model;
    ModelStep step;
    {
      ModelRecorder recorder(model);
      model.nodes[0].rotation.x = -0.0f;
      if (add_mesh) model.meshes.push_back({"more", {Primitive{}}, ""});
      step = recorder.finish();
    }
    ASSERT_TRUE(step.change().structure) << add_mesh;
    const Model after = model;
    for (int cycle = 0; cycle < 2; ++cycle) {
      step.undo(model);
      expect_same(model, before, "undo");
      EXPECT_FALSE(std::signbit(model.nodes[0].rotation.x)) << add_mesh;
      step.redo(model);
      expect_same(model, after, "redo");
      EXPECT_TRUE(std::signbit(model.nodes[0].rotation.x)) << add_mesh;
    }
  }
}

}  // namespace
}  // namespace deepcut
