// SPDX-License-Identifier: MIT
// Morph targets through the glTF writer: what the reader keeps (inputs built in the test, and the
// sample models) survives read -> write -> read float-exact (targets, names, deltas, mesh and
// node weights, weight channels) with 0 validator errors; deltas match an independent decoding
// of the sample files; a mesh that lost its targets takes its channels along; a drilled mesh
// writes the deltas of its new vertices and corners.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include <nlohmann/json.hpp>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/drill.h"
#include "deepcut/core/validate.h"
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

const std::string kAssets = DEEPCUT_ASSETS_DIR;
const std::vector<std::string> kMorphModels = {kAssets + "/models/AnimatedMorphCube/AnimatedMorphCube.gltf",
                                               kAssets + "/models/AnimatedMorphSphere/AnimatedMorphSphere.gltf",
                                               kAssets + "/models/SimpleMorph/SimpleMorph.gltf"};

std::vector<unsigned char> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), {});
}

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

// A dense float VEC3 accessor of a .gltf with external buffers, decoded without the reader.
std::vector<glm::vec3> decode_vec3(const json& doc, const std::string& dir, int accessor) {
  const json& acc = doc["accessors"][std::size_t(accessor)];
  const json& view = doc["bufferViews"][acc["bufferView"].get<std::size_t>()];
  const auto buffer = file_bytes(dir + "/" + doc["buffers"][view["buffer"].get<std::size_t>()]["uri"].get<std::string>());
  const std::size_t offset = view.value("byteOffset", std::size_t(0)) + acc.value("byteOffset", std::size_t(0));
  const std::size_t stride = view.value("byteStride", std::size_t(12));
  std::vector<glm::vec3> out(acc["count"].get<std::size_t>());
  for (std::size_t i = 0; i < out.size(); ++i) std::memcpy(&out[i], buffer.data() + offset + i * stride, 12);
  return out;
}

std::vector<std::uint32_t> decode_indices(const json& doc, const std::string& dir, int accessor) {
  const json& acc = doc["accessors"][std::size_t(accessor)];
  const json& view = doc["bufferViews"][acc["bufferView"].get<std::size_t>()];
  const auto buffer = file_bytes(dir + "/" + doc["buffers"][view["buffer"].get<std::size_t>()]["uri"].get<std::string>());
  const std::size_t offset = view.value("byteOffset", std::size_t(0)) + acc.value("byteOffset", std::size_t(0));
  std::vector<std::uint32_t> out(acc["count"].get<std::size_t>());
  for (std::size_t i = 0; i < out.size(); ++i) {
    std::uint16_t v;
    std::memcpy(&v, buffer.data() + offset + 2 * i, 2);
    out[i] = v;
  }
  return out;
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

TEST(GltfMorphTest, sample_models_read_the_files_deltas_exactly) {
  for (const std::string& path : kMorphModels) {
    SCOPED_TRACE(path);
    const json doc = json::parse(file_bytes(path));
    const std::string dir = fs::path(path).parent_path().string();
    const json& prim = doc["meshes"][0]["primitives"][0];
    ASSERT_EQ(doc["accessors"][prim["indices"].get<std::size_t>()]["componentType"], 5123);
    const auto indices = decode_indices(doc, dir, prim["indices"]);
    const Model model = read_gltf(path);
    ASSERT_EQ(model.meshes.size(), 1u);
    const Mesh& mesh = model.meshes[0];
    ASSERT_EQ(mesh.target_count(), prim["targets"].size());
    EXPECT_EQ(mesh.weights, doc["meshes"][0]["weights"].get<std::vector<float>>());
    const SurfaceMesh& sm = mesh.primitives[0].mesh;
    ASSERT_EQ(sm.face_count() * 3, indices.size());
    for (std::size_t t = 0; t < mesh.target_count(); ++t) {
      const json& target = prim["targets"][t];
      const int i = static_cast<int>(t);
      for (const char* name : {"POSITION", "NORMAL", "TANGENT"}) {
        if (!target.contains(name)) continue;
        const auto file = decode_vec3(doc, dir, target[name]);
        std::size_t differ = 0;
        for (std::size_t c = 0; c < indices.size(); ++c) {
          const glm::vec3 want = file[indices[c]];
          glm::vec3 got;
          if (std::string(name) == "POSITION")
            got = sm.vertex_attrs().get<glm::vec3>(attr::morph_position_name(i))[sm.face(FaceId(std::uint32_t(c / 3)))[c % 3].index];
          else
            got = sm.corner_attrs().get<glm::vec3>(std::string(name) == "NORMAL" ? attr::morph_normal_name(i) : attr::morph_tangent_name(i))[c];
          differ += got != want;
        }
        EXPECT_EQ(differ, 0u) << "target " << t << " " << name;
      }
    }
    // The weight channel: one value per target per key.
    const json& sampler = doc["animations"][0]["samplers"][0];
    ASSERT_EQ(model.animations.size(), 1u);
    ASSERT_EQ(model.animations[0].channels.size(), 1u);
    EXPECT_EQ(model.animations[0].channels[0].path, AnimationPath::Weights);
    const AnimationSampler& s = model.animations[0].samplers[0];
    EXPECT_EQ(std::size_t(s.components), mesh.target_count());
    EXPECT_EQ(s.input.size(), doc["accessors"][sampler["input"].get<std::size_t>()]["count"].get<std::size_t>());
    EXPECT_EQ(s.output.size(), doc["accessors"][sampler["output"].get<std::size_t>()]["count"].get<std::size_t>());
    EXPECT_FALSE(has_note(model, "morph")) << notes_of(model);
  }
}

TEST(GltfMorphTest, sample_models_round_trip_targets_weights_and_channels) {
  const std::string dir = test::temp_dir("morph-round-trip");
  for (const std::string& path : kMorphModels) {
    for (const bool weld : {true, false}) {
      SCOPED_TRACE(path + (weld ? " welded" : " unwelded"));
      const Model model = read_gltf(path, ImportOptions{weld});
      expect_round_trip(model, dir + "/" + fs::path(path).stem().string() + ".glb");
      expect_round_trip(model, dir + "/" + fs::path(path).stem().string() + ".gltf");
    }
  }
  fs::remove_all(dir);
}

// What the writer does when the model no longer matches its channels: a mesh that lost its
// targets takes its node weights and channels along, so the file stays valid.
TEST(GltfMorphTest, export_drops_channels_of_meshes_without_targets_and_writes_the_deltas_of_new_vertices) {
  const std::string dir = test::temp_dir("morph-export");
  {
    Model model = read_gltf(kMorphModels[0]);
    model.nodes[0].weights = {1.0f, 0.0f};
    for (auto& prim : model.meshes[0].primitives)
      for (int i = 0; i < 2; ++i) {
        prim.mesh.vertex_attrs().remove(attr::morph_position_name(i));
        prim.mesh.corner_attrs().remove(attr::morph_normal_name(i));
      }
    write_gltf(model, dir + "/untargeted.glb");
    const auto v = test::validate_gltf(dir + "/untargeted.glb");
    EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
    const Model again = read_gltf(dir + "/untargeted.glb");
    EXPECT_EQ(again.meshes[0].target_count(), 0u);
    EXPECT_TRUE(again.nodes[0].weights.empty());
    EXPECT_TRUE(again.animations.empty() || again.animations[0].channels.empty());
  }
  {  // a drilled sphere: new vertices and corners, deltas blended by MeshEditor
    Model model = read_gltf(kMorphModels[1]);
    const BoundingBox box = compute_stats(model).bounds;  // the drill works in the posed (world) frame
    const glm::vec3 c = 0.5f * (box.min + box.max), d(0.0f, 0.0f, box.diagonal());
    const std::size_t before = model.meshes[0].primitives[0].mesh.vertex_count();
    drill_model(model, Cylinder{c - d, c + d, 0.05f * box.diagonal()});
    ASSERT_GT(model.meshes[0].primitives[0].mesh.vertex_count(), before);
    write_gltf(model, dir + "/drilled.glb");
    const auto v = test::validate_gltf(dir + "/drilled.glb");
    EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
    const Model again = read_gltf(dir + "/drilled.glb");
    ASSERT_EQ(again.meshes.size(), model.meshes.size());
    for (std::size_t m = 0; m < model.meshes.size(); ++m) {
      EXPECT_EQ(again.meshes[m].target_count(), 2u) << "mesh " << m;
      ASSERT_EQ(again.meshes[m].primitives.size(), model.meshes[m].primitives.size());
      for (std::size_t p = 0; p < model.meshes[m].primitives.size(); ++p)
        expect_same_targets(model.meshes[m].primitives[p], again.meshes[m].primitives[p], 2);
    }
    expect_same_weight_channels(model, again);
  }
  fs::remove_all(dir);
}

}  // namespace deepcut
