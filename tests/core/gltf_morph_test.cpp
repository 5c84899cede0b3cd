// SPDX-License-Identifier: MIT
// Morph targets through the glTF writer: what the reader keeps (inputs built in the test)
// survives read -> write -> read float-exact (targets, names, deltas, mesh and node weights,
// weight channels) with 0 validator errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "deepcut/core/io/gltf.h"
#include "fixtures.h"
#include "gltf_morph_fixtures.h"
#include "tools.h"

namespace deepcut {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;
using morph_test::has_note;
using morph_test::notes_of;
using morph_test::Tiny;

// Bitwise equality of two float vectors (so -0 and NaN would show, and the check is exact).
bool same_bits(const glm::vec3& a, const glm::vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0 || a == b; }

// Every corner of every face: the corner's position, each target's position delta of its vertex
// and the corner's normal / tangent deltas. Faces keep the file's order through read and write,
// so two reads of one model compare corner by corner, whatever the weld did to the vertices.
void expect_same_targets(const Primitive& a, const Primitive& b, std::size_t targets) {
  SurfaceMesh ma = a.mesh, mb = b.mesh;  // as written: without the faces an operation deleted
  ma.compact();
  mb.compact();
  ASSERT_EQ(ma.face_count(), mb.face_count());
  for (std::size_t t = 0; t < targets; ++t) {
    const int i = static_cast<int>(t);
    const auto& pa = ma.vertex_attrs().get<glm::vec3>(attr::morph_position_name(i));
    const auto& pb = mb.vertex_attrs().get<glm::vec3>(attr::morph_position_name(i));
    for (const std::string& name : {attr::morph_normal_name(i), attr::morph_tangent_name(i)})
      EXPECT_EQ(ma.corner_attrs().contains(name), mb.corner_attrs().contains(name)) << name;
    const auto* na = ma.corner_attrs().find<glm::vec3>(attr::morph_normal_name(i));
    const auto* nb = mb.corner_attrs().find<glm::vec3>(attr::morph_normal_name(i));
    const auto* ta = ma.corner_attrs().find<glm::vec3>(attr::morph_tangent_name(i));
    const auto* tb = mb.corner_attrs().find<glm::vec3>(attr::morph_tangent_name(i));
    std::size_t differ = 0;
    for (std::uint32_t f = 0; f < ma.face_slots(); ++f)
      for (int k = 0; k < 3; ++k) {
        const std::size_t c = 3 * std::size_t(f) + std::size_t(k);
        const VertexId va = ma.face(FaceId(f))[k], vb = mb.face(FaceId(f))[k];
        differ += !same_bits(ma.position(va), mb.position(vb)) || !same_bits(pa[va.index], pb[vb.index]);
        if (na && nb) differ += !same_bits((*na)[c], (*nb)[c]);
        if (ta && tb) differ += !same_bits((*ta)[c], (*tb)[c]);
      }
    EXPECT_EQ(differ, 0u) << "target " << t << ": corners whose position or deltas changed";
  }
}

// Every weight channel, in order (animations left without any channel are not written).
void expect_same_weight_channels(const Model& a, const Model& b) {
  struct Found {
    const Animation* anim;
    AnimationChannel channel;
  };
  auto weight_channels = [](const Model& m) {
    std::vector<Found> out;
    for (const auto& anim : m.animations)
      for (const auto& c : anim.channels)
        if (c.path == AnimationPath::Weights) out.push_back({&anim, c});
    return out;
  };
  const auto ca = weight_channels(a), cb = weight_channels(b);
  ASSERT_EQ(ca.size(), cb.size());
  for (std::size_t c = 0; c < ca.size(); ++c) {
    EXPECT_EQ(ca[c].anim->name, cb[c].anim->name);
    EXPECT_EQ(ca[c].channel.node, cb[c].channel.node);
    const AnimationSampler& sa = ca[c].anim->samplers[std::size_t(ca[c].channel.sampler)];
    const AnimationSampler& sb = cb[c].anim->samplers[std::size_t(cb[c].channel.sampler)];
    EXPECT_EQ(sa.components, sb.components);
    EXPECT_EQ(sa.interpolation, sb.interpolation);
    EXPECT_EQ(sa.input, sb.input);
    EXPECT_EQ(sa.output, sb.output);
  }
}

// The model's targets equal the file's: read → write → read keeps them (float-exact), and the
// written file is valid glTF.
void expect_round_trip(const Model& model, const std::string& out) {
  write_gltf(model, out);
  const auto v = test::validate_gltf(out);
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
  const Model again = read_gltf(out);
  ASSERT_EQ(again.meshes.size(), model.meshes.size());
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    const Mesh& a = model.meshes[m];
    const Mesh& b = again.meshes[m];
    EXPECT_EQ(a.target_count(), b.target_count());
    EXPECT_EQ(a.weights, b.weights);
    EXPECT_EQ(a.target_names, b.target_names);
    EXPECT_EQ(a.extras_json, b.extras_json);
    ASSERT_EQ(a.primitives.size(), b.primitives.size());
    for (std::size_t p = 0; p < a.primitives.size(); ++p) expect_same_targets(a.primitives[p], b.primitives[p], a.target_count());
  }
  for (std::size_t n = 0; n < model.nodes.size(); ++n) EXPECT_EQ(model.nodes[n].weights, again.nodes[n].weights);
  expect_same_weight_channels(model, again);
}

}  // namespace

TEST(GltfMorphTest, inputs_built_in_the_test_round_trip_with_zero_validator_errors) {
  const std::string dir = test::temp_dir("morph-tiny");
  std::vector<std::pair<std::string, Tiny>> inputs = {{"quad.glb", morph_test::tiny_quad()},
                                                      {"coincident.glb", morph_test::coincident_quad()}};
  {  // channels the reader drops (see gltf_morph_read_test.cpp)
    Tiny t = morph_test::tiny_quad();
    morph_test::add_weights_channel(t, {0, 1}, {0, 0, 0, 1, 1, 1}, 0);
    morph_test::add_weights_channel(t, {0, 1}, {0, 1}, 1);
    inputs.emplace_back("channels.glb", t);
  }
  {  // weights of the wrong length, a NORMAL delta without a base NORMAL
    Tiny t = morph_test::tiny_quad();
    t.doc["meshes"][0]["weights"] = {0.5, 0.5, 0.5};
    t.doc["nodes"][0]["weights"] = {1.0};
    t.doc["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL");
    inputs.emplace_back("lengths.glb", t);
  }
  {  // two primitives with 2 and 1 targets
    Tiny t = morph_test::tiny_quad();
    json second = t.doc["meshes"][0]["primitives"][0];
    second["targets"].erase(1);
    t.doc["meshes"][0]["primitives"].push_back(second);
    inputs.emplace_back("unequal.glb", t);
  }
  for (const auto& [name, tiny] : inputs) {
    SCOPED_TRACE(name);
    const Model model = read_gltf_memory(tiny.glb(), name);
    expect_round_trip(model, dir + "/" + name);
  }
  fs::remove_all(dir);
}

}  // namespace deepcut
