// SPDX-License-Identifier: MIT
// Morph targets through the glTF reader and the weld, on inputs built in the test: sparse
// targets, names, mesh and node weights and every interpolation read as the file says; coincident
// vertices that morph apart stay apart; hostile morph data is refused with one line or dropped
// with a note, never a crash.
#include <gtest/gtest.h>

#include <limits>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/weld.h"
#include "gltf_morph_fixtures.h"

namespace deepcut {
namespace {

using morph_test::has_note;
using morph_test::notes_of;
using morph_test::Tiny;
using morph_test::coincident_quad;
using morph_test::tiny_quad;
using nlohmann::json;

// Reads a spoiled `t`: a one-line error naming the input that contains `part`.
void expect_refused(const Tiny& t, const std::string& part) {
  try {
    read_gltf_memory(t.glb(), "bad.glb");
    ADD_FAILURE() << "accepted, expected an error with: " << part;
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
    EXPECT_EQ(what.rfind("bad.glb: ", 0), 0u) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_NE(what.find(part), std::string::npos) << what;
  }
}

}  // namespace

TEST(GltfMorphReadTest, sparse_targets_names_node_weights_and_every_interpolation_read_as_the_file_says) {
  const Model model = read_gltf_memory(tiny_quad().glb(), "quad.glb");
  EXPECT_TRUE(model.import_notes.empty()) << notes_of(model);
  const Mesh& mesh = model.meshes[0];
  ASSERT_EQ(mesh.target_count(), 2u);
  EXPECT_EQ(mesh.weights, (std::vector<float>{0.25f, 0.75f}));
  EXPECT_EQ(mesh.target_names, (std::vector<std::string>{"lift", "tilt"}));
  EXPECT_NE(mesh.extras_json.find("\"author\""), std::string::npos);
  EXPECT_EQ(model.nodes[0].weights, (std::vector<float>{1.0f, 0.0f}));
  EXPECT_TRUE(model.nodes[1].weights.empty());
  const SurfaceMesh& sm = mesh.primitives[0].mesh;
  ASSERT_EQ(sm.vertex_count(), 4u);  // indexed: vertex v is glTF vertex v
  const auto& lift = sm.vertex_attrs().get<glm::vec3>(attr::morph_position_name(0));
  const auto& tilt = sm.vertex_attrs().get<glm::vec3>(attr::morph_position_name(1));
  EXPECT_EQ(lift[2], glm::vec3(0, 0, 0.5f));  // sparse over zeros (no bufferView)
  EXPECT_EQ(lift[1], glm::vec3(0.0f));
  EXPECT_EQ(tilt[1], glm::vec3(0, 0, 0.25f));  // dense base
  EXPECT_EQ(tilt[2], glm::vec3(0, 0, 0.25f));  // sparse override of a zero
  EXPECT_FALSE(sm.corner_attrs().contains(attr::morph_normal_name(0)));
  EXPECT_FALSE(sm.corner_attrs().contains(attr::morph_tangent_name(1)));
  const auto& turn = sm.corner_attrs().get<glm::vec3>(attr::morph_normal_name(1));
  EXPECT_EQ(turn[1], glm::vec3(-0.1f, 0, 0));  // face 0 corner 1 is vertex 1
  EXPECT_EQ(turn[0], glm::vec3(0.0f));
  ASSERT_EQ(model.animations.size(), 2u);
  ASSERT_EQ(model.animations[0].channels.size(), 1u);
  EXPECT_EQ(model.animations[0].channels[0].path, AnimationPath::Weights);
  EXPECT_EQ(model.animations[0].channels[0].node, 0);
  const AnimationSampler& cubic = model.animations[0].samplers[0];
  EXPECT_EQ(cubic.interpolation, Interpolation::CubicSpline);
  EXPECT_EQ(cubic.components, 2);
  EXPECT_EQ(cubic.output.size(), 12u);
  const AnimationSampler& step = model.animations[1].samplers[0];
  EXPECT_EQ(step.interpolation, Interpolation::Step);
  EXPECT_EQ(step.components, 2);
  EXPECT_EQ(step.output, (std::vector<float>{0, 0, 1, 0, 0, 1}));
}

TEST(GltfMorphReadTest, weld_keeps_coincident_vertices_that_morph_apart) {
  for (const WeldKey key : {WeldKey::PositionAndSkin, WeldKey::Position}) {
    SurfaceMesh mesh;
    for (const glm::vec3 p : {glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), glm::vec3(1, 1, 0), glm::vec3(0, 0, 0), glm::vec3(1, 1, 0),
                              glm::vec3(0, 1, 0)})
      mesh.add_vertex(p);
    mesh.add_face(VertexId(0), VertexId(1), VertexId(2));
    mesh.add_face(VertexId(3), VertexId(4), VertexId(5));
    auto& delta = mesh.vertex_attrs().add<glm::vec3>(attr::morph_position_name(0));
    delta[0] = glm::vec3(0, 0, 1);
    delta[2] = delta[4] = glm::vec3(0, 0, 2);
    const WeldReport r = weld(mesh, {key});
    EXPECT_EQ(mesh.vertex_count(), 5u) << "key " << int(key);
    EXPECT_EQ(r.merged, 1u);
    if (key == WeldKey::PositionAndSkin) {
      EXPECT_EQ(r.kept_apart, 1u);
    }
  }
  const Model model = read_gltf_memory(coincident_quad().glb(), "coincident.glb");
  EXPECT_EQ(model.meshes[0].primitives[0].mesh.vertex_count(), 5u);
  EXPECT_TRUE(has_note(model, "different skin weights or morph deltas (kept apart)")) << notes_of(model);
}

TEST(GltfMorphReadTest, hostile_targets_are_refused_with_one_line) {
  {  // a target with fewer deltas than the primitive has vertices
    Tiny t = tiny_quad();
    t.doc["meshes"][0]["primitives"][0]["targets"][1]["POSITION"] = t.floats({0, 0, 0, 0, 0, 0, 0, 0, 0}, "VEC3", 3);
    expect_refused(t, "morph target 1 POSITION has 3 elements, POSITION has 4");
  }
  {  // a NaN delta
    Tiny t = tiny_quad();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    t.doc["meshes"][0]["primitives"][0]["targets"][1]["NORMAL"] = t.floats({0, 0, 0, nan, 0, 0, 0, 0, 0, 0, 0, 0}, "VEC3", 3);
    expect_refused(t, "morph target 1 NORMAL delta 1 is not finite");
  }
  {  // a target naming an accessor that does not exist
    Tiny t = tiny_quad();
    t.doc["meshes"][0]["primitives"][0]["targets"][0]["POSITION"] = 99;
    expect_refused(t, "accessor");
  }
  {  // a SCALAR target
    Tiny t = tiny_quad();
    t.doc["meshes"][0]["primitives"][0]["targets"][0]["POSITION"] = t.floats({0, 0, 0, 0}, "SCALAR", 1);
    expect_refused(t, "morph target 0 POSITION is not VEC3");
  }
  {  // an overflowing weight
    Tiny t = tiny_quad();
    t.doc["nodes"][0]["weights"] = {1e300, 0.0};
    expect_refused(t, "node 0: a morph weight is not finite");
  }
  {  // a small file listing a target a hundred thousand times
    Tiny t = tiny_quad();
    json targets = json::array();
    const int one = t.sparse_vec3(4, {0}, {0, 0, 1});
    for (int i = 0; i < 200000; ++i) targets.push_back({{"POSITION", one}});
    t.doc["meshes"][0]["primitives"][0]["targets"] = targets;
    t.doc["meshes"][0].erase("weights");
    t.doc["nodes"][0].erase("weights");
    t.doc.erase("animations");
    expect_refused(t, "claims far more data than it holds");
  }
}

TEST(GltfMorphReadTest, weights_that_do_not_fit_the_targets_are_dropped_or_resized_with_a_note) {
  {  // channels whose outputs are no whole number per key, the wrong number per key, that drive
     // a node without targets, or drive weights another channel already drives
    Tiny t = tiny_quad();
    morph_test::add_weights_channel(t, {0, 1}, {0, 0, 1, 1, 1}, 0);
    morph_test::add_weights_channel(t, {0, 1}, {0, 0, 0, 1, 1, 1}, 0);
    morph_test::add_weights_channel(t, {0, 1}, {0, 1}, 1);
    morph_test::add_weights_channel(t, {0, 1}, {0, 0, 1, 1}, 0);
    const Model model = read_gltf_memory(t.glb(), "channels.glb");
    EXPECT_TRUE(has_note(model, "morph weight channel dropped: animation 0 channel 1 (5 weights for 2 key times, not a whole number per key)")) << notes_of(model);
    EXPECT_TRUE(has_note(model, "on node 0 'quad' (3 weights per key for 2 morph targets)")) << notes_of(model);
    EXPECT_TRUE(has_note(model, "on node 1 'empty' (its mesh has no morph targets)")) << notes_of(model);
    EXPECT_TRUE(has_note(model, "(another channel drives the same weights)")) << notes_of(model);
    ASSERT_EQ(model.animations[0].channels.size(), 1u);
    EXPECT_EQ(model.animations[0].samplers.size(), 1u) << "the samplers of dropped channels go too";
    EXPECT_EQ(model.animations[0].samplers[0].interpolation, Interpolation::CubicSpline);
  }
  {  // mesh and node weights of the wrong length, a NORMAL delta without a base NORMAL
    Tiny t = tiny_quad();
    t.doc["meshes"][0]["weights"] = {0.5, 0.5, 0.5};
    t.doc["nodes"][0]["weights"] = {1.0};
    t.doc["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL");
    const Model model = read_gltf_memory(t.glb(), "lengths.glb");
    EXPECT_EQ(model.meshes[0].weights, (std::vector<float>{0.5f, 0.5f}));
    EXPECT_EQ(model.nodes[0].weights, (std::vector<float>{1.0f, 0.0f}));
    EXPECT_FALSE(model.meshes[0].primitives[0].mesh.corner_attrs().contains(attr::morph_normal_name(1)));
    EXPECT_TRUE(has_note(model, "1 mesh's morph weights resized to its target count: mesh 0 (3 weights for 2 targets)")) << notes_of(model);
    EXPECT_TRUE(has_note(model, "1 node's morph weights resized to its mesh's target count: node 0 'quad' (1 weights for 2 targets)")) << notes_of(model);
    EXPECT_TRUE(has_note(model, "1 morph NORMAL/TANGENT delta dropped (the primitive has no such attribute to morph): mesh 0 primitive 0")) << notes_of(model);
  }
  {  // two primitives with 2 and 1 targets: the first target is kept, and its name
    Tiny t = tiny_quad();
    json second = t.doc["meshes"][0]["primitives"][0];
    second["targets"].erase(1);
    t.doc["meshes"][0]["primitives"].push_back(second);
    const Model model = read_gltf_memory(t.glb(), "unequal.glb");
    EXPECT_EQ(model.meshes[0].target_count(), 1u);
    EXPECT_EQ(model.meshes[0].target_names, (std::vector<std::string>{"lift"}));
    EXPECT_NE(model.meshes[0].extras_json.find("\"author\""), std::string::npos);
    EXPECT_EQ(model.nodes[0].weights, (std::vector<float>{1.0f}));
    EXPECT_TRUE(has_note(model, "1 morph target dropped (the mesh's primitives must all have it): mesh 0 (1 to 2 per primitive, the first 1 kept)")) << notes_of(model);
    EXPECT_TRUE(has_note(model, "1 mesh's extras.targetNames cut to the targets kept: mesh 0")) << notes_of(model);
    for (const auto& a : model.animations) EXPECT_TRUE(a.channels.empty()) << "2 weights per key no longer fit";
  }
  {  // a mesh without targets but with weights and target names
    Tiny t = tiny_quad();
    t.doc["meshes"][0]["primitives"][0].erase("targets");
    t.doc.erase("animations");
    const Model model = read_gltf_memory(t.glb(), "untargeted.glb");
    EXPECT_EQ(model.meshes[0].target_count(), 0u);
    EXPECT_TRUE(model.nodes[0].weights.empty());
    EXPECT_TRUE(has_note(model, "mesh's morph weights resized to its target count: mesh 0 (2 weights for 0 targets)")) << notes_of(model);
  }
}

}  // namespace deepcut
