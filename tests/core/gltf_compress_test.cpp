// SPDX-License-Identifier: MIT
// Compressed glTF: the Draco and meshopt files of real models read like their uncompressed
// sources (counts equal, positions and skin weights within the codec's quantisation), and
// `Compression::Draco` / `Compression::Meshopt` exports validate and read back to the same
// geometry (meshopt exactly, Draco within its quantisation).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/validate.h"
#include "fixtures.h"
#include "gltf_morph_fixtures.h"
#include "tools.h"

namespace deepcut {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string asset(const std::string& rel) { return std::string(DEEPCUT_ASSETS_DIR) + "/" + rel; }

std::size_t uv_sets(const Model& m) {
  std::size_t most = 0;
  for (const auto& mesh : m.meshes)
    for (const auto& prim : mesh.primitives) {
      std::size_t n = 0;
      for (const auto& name : prim.mesh.corner_attrs().names()) n += name.rfind("c:uv", 0) == 0;
      most = std::max(most, n);
    }
  return most;
}

// A vertex's influences as joint -> weight.
std::map<int, float> influences(const SurfaceMesh& mesh, VertexId v) {
  std::map<int, float> out;
  const auto& va = mesh.vertex_attrs();
  const char* jn[2] = {attr::kJoints0, attr::kJoints1};
  const char* wn[2] = {attr::kWeights0, attr::kWeights1};
  for (int s = 0; s < 2; ++s) {
    const auto* j = va.find<glm::u16vec4>(jn[s]);
    const auto* w = va.find<glm::vec4>(wn[s]);
    if (!j || !w) break;
    for (int c = 0; c < 4; ++c)
      if ((*w)[v.index][c] > 0.0f) out[(*j)[v.index][c]] += (*w)[v.index][c];
  }
  return out;
}

float influence_distance(const std::map<int, float>& a, const std::map<int, float>& b) {
  float d = 0.0f;
  for (const auto& [j, w] : a) d += std::abs(w - (b.count(j) ? b.at(j) : 0.0f));
  for (const auto& [j, w] : b)
    if (!a.count(j)) d += w;
  return d;
}

// `got` has the counts of `want` and each of its vertices lies within `tolerance` of a vertex of
// `want` with influences within `weight_tolerance` (L1), primitive by primitive.
void expect_same_geometry(const Model& want, const Model& got, float tolerance, float weight_tolerance) {
  const ModelStats a = compute_stats(want), b = compute_stats(got);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.welded_vertices, b.welded_vertices);
  EXPECT_EQ(a.joints, b.joints);
  EXPECT_EQ(a.skins, b.skins);
  EXPECT_EQ(a.animations, b.animations);
  EXPECT_EQ(uv_sets(want), uv_sets(got));
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(a.bounds.min[c], b.bounds.min[c], tolerance);
    EXPECT_NEAR(a.bounds.max[c], b.bounds.max[c], tolerance);
  }
  // Posed, not bind-space: a quantised file (KHR_mesh_quantization) stores its skinned positions
  // in another frame and compensates in the inverse bind matrices.
  const PosedModel wp = PosedModel::build(want, -1, 0.0f, PoseDetail::Positions);
  const PosedModel gp = PosedModel::build(got, -1, 0.0f, PoseDetail::Positions);
  ASSERT_EQ(wp.instances().size(), gp.instances().size());
  for (const auto& [key, wi] : wp.instances()) {
    ASSERT_TRUE(gp.instances().count(key));
    const PosedMesh& gi = gp.instances().at(key);
    const SurfaceMesh& wm = want.meshes[std::size_t(wi.mesh)].primitives[std::size_t(wi.primitive)].mesh;
    const SurfaceMesh& gm = got.meshes[std::size_t(gi.mesh)].primitives[std::size_t(gi.primitive)].mesh;
    std::size_t off = 0, worst_weights = 0;
    for (std::uint32_t v = 0; v < gm.vertex_count(); ++v) {
      float best = INFINITY, best_weights = INFINITY;
      for (std::uint32_t w = 0; w < wm.vertex_count(); ++w) {
        const float d = glm::length(wi.posed[w] - gi.posed[v]);
        best = std::min(best, d);
        if (d <= tolerance)
          best_weights = std::min(best_weights, influence_distance(influences(wm, VertexId(w)), influences(gm, VertexId(v))));
      }
      off += !(best <= tolerance);
      worst_weights += !(best_weights <= weight_tolerance);
    }
    EXPECT_EQ(off, 0u) << "vertices farther than " << tolerance << " from every source vertex";
    EXPECT_EQ(worst_weights, 0u) << "vertices whose skin weights moved by more than " << weight_tolerance;
  }
}

float model_size(const Model& m) {
  const auto b = compute_stats(m).bounds;
  return glm::length(b.max - b.min);
}

TEST(CompressedGltf, draco_cesium_man_reads_like_its_source) {
  const Model source = read_gltf(asset("models/CesiumMan/CesiumMan.glb"));
  const Model draco = read_gltf(asset("models/compressed/CesiumMan-draco.glb"));
  // gltf-transform's defaults: positions 14 bits, weights 8 bits.
  expect_same_geometry(source, draco, 2e-4f * model_size(source), 0.02f);
}

TEST(CompressedGltf, meshopt_fox_reads_like_its_source) {
  const Model source = read_gltf(asset("models/Fox/Fox.glb"));
  const Model meshopt = read_gltf(asset("models/compressed/Fox-meshopt.glb"));
  expect_same_geometry(source, meshopt, 2e-4f * model_size(source), 0.02f);
  // The animation data went through the QUATERNION and EXPONENTIAL filters.
  ASSERT_EQ(source.animations.size(), meshopt.animations.size());
  for (std::size_t a = 0; a < source.animations.size(); ++a) EXPECT_NEAR(source.animations[a].duration(), meshopt.animations[a].duration(), 1e-4f);
}

json read_json(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() >= 20 && std::equal(bytes.begin(), bytes.begin() + 4, "glTF")) {
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, 4);
    return json::parse(bytes.begin() + 20, bytes.begin() + 20 + length);
  }
  return json::parse(bytes.begin(), bytes.end());
}

bool lists(const json& doc, const char* key, const std::string& name) {
  return doc.contains(key) && std::find(doc[key].begin(), doc[key].end(), name) != doc[key].end();
}

class CompressedExport : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override { dir_ = test::temp_dir("compress"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string dir_;
};

TEST_P(CompressedExport, validates_and_reads_back_to_the_same_geometry) {
  const Model model = read_gltf(GetParam());
  const float size = model_size(model);
  struct Codec {
    Compression compression;
    const char* name;
    const char* extension;
    float tolerance;  // of the model's size
  };
  for (const Codec& codec : {Codec{Compression::Draco, "draco", "KHR_draco_mesh_compression", 2e-4f},
                             Codec{Compression::Meshopt, "meshopt", "EXT_meshopt_compression", 0.0f}}) {
    for (const char* ext : {".glb", ".gltf"}) {
      SCOPED_TRACE(std::string(codec.name) + ext);
      const std::string out = dir_ + "/" + fs::path(GetParam()).stem().string() + "-" + codec.name + ext;
      ExportOptions options;
      options.compression = codec.compression;
      write_gltf(model, out, options);
      const auto v = test::validate_gltf(out);
      EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
      const json doc = read_json(out);
      EXPECT_TRUE(lists(doc, "extensionsUsed", codec.extension) && lists(doc, "extensionsRequired", codec.extension));
      const Model back = read_gltf(out);
      expect_same_geometry(model, back, codec.tolerance * size, 1e-5f);
    }
  }
}

std::vector<std::string> export_models() {
  return {asset("models/CesiumMan/CesiumMan.glb"), asset("models/Fox/Fox.glb"), asset("models/RiggedFigure/RiggedFigure.glb"),
          asset("models/RiggedSimple/RiggedSimple.gltf"), asset("models/SimpleSkin/SimpleSkin.gltf"), asset("cactus.glb")};
}

INSTANTIATE_TEST_SUITE_P(Assets, CompressedExport, ::testing::ValuesIn(export_models()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           std::string name = fs::path(param.param).stem().string();
                           name.erase(std::remove_if(name.begin(), name.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); }), name.end());
                           return name;
                         });

TEST(CompressedGltf, export_is_uncompressed_by_default) {
  const std::string dir = test::temp_dir("compress-default");
  write_gltf(read_gltf(asset("models/compressed/Fox-meshopt.glb")), dir + "/fox.glb");
  const json doc = read_json(dir + "/fox.glb");
  for (const char* ext : {"EXT_meshopt_compression", "KHR_draco_mesh_compression", "KHR_mesh_quantization"})
    EXPECT_FALSE(lists(doc, "extensionsUsed", ext) || lists(doc, "extensionsRequired", ext)) << ext;
  EXPECT_EQ(doc["buffers"].size(), 1u);
  fs::remove_all(dir);
}

TEST(CompressedGltf, compression_names_parse) {
  Compression c = Compression::None;
  EXPECT_TRUE(parse_compression("draco", &c));
  EXPECT_EQ(c, Compression::Draco);
  EXPECT_TRUE(parse_compression("meshopt", &c));
  EXPECT_EQ(c, Compression::Meshopt);
  EXPECT_TRUE(parse_compression("none", &c));
  EXPECT_EQ(c, Compression::None);
  EXPECT_FALSE(parse_compression("zip", &c));
}

// Morph targets stay plain accessors beside a Draco primitive (which keeps the vertex order for
// them) and go through meshopt like any view: every target, weight, name and weight channel reads
// back, the deltas exactly, on the test's own quad and on a real morph model.
void expect_same_targets(const Model& want, const Model& got, float tolerance) {
  ASSERT_EQ(want.meshes.size(), got.meshes.size());
  for (std::size_t m = 0; m < want.meshes.size(); ++m) {
    EXPECT_EQ(want.meshes[m].weights, got.meshes[m].weights);
    EXPECT_EQ(want.meshes[m].target_names, got.meshes[m].target_names);
    for (std::size_t p = 0; p < want.meshes[m].primitives.size(); ++p) {
      const SurfaceMesh& wm = want.meshes[m].primitives[p].mesh;
      const SurfaceMesh& gm = got.meshes[m].primitives[p].mesh;
      for (std::size_t t = 0; t < want.meshes[m].target_count(); ++t) {
        const auto* wd = wm.vertex_attrs().find<glm::vec3>(attr::morph_position_name(static_cast<int>(t)));
        const auto* gd = gm.vertex_attrs().find<glm::vec3>(attr::morph_position_name(static_cast<int>(t)));
        ASSERT_TRUE(wd && gd) << "target " << t;
        std::size_t unmatched = 0;
        for (std::uint32_t v = 0; v < gm.vertex_count(); ++v) {
          bool found = false;
          for (std::uint32_t w = 0; w < wm.vertex_count() && !found; ++w)
            found = glm::length(wm.position(VertexId(w)) - gm.position(VertexId(v))) <= tolerance && (*wd)[w] == (*gd)[v];
          unmatched += !found;
        }
        EXPECT_EQ(unmatched, 0u) << "vertices of target " << t << " whose delta is not a source vertex's";
      }
    }
  }
  std::size_t want_channels = 0, got_channels = 0;
  for (const auto& a : want.animations)
    for (const auto& c : a.channels) want_channels += c.path == AnimationPath::Weights;
  for (const auto& a : got.animations)
    for (const auto& c : a.channels) got_channels += c.path == AnimationPath::Weights;
  EXPECT_EQ(want_channels, got_channels);
}

void round_trip_targets(const Model& model, const std::string& stem) {
  const std::string dir = test::temp_dir("compress-morph");
  const float size = model_size(model);
  for (const auto& [compression, name] : {std::pair{Compression::Draco, "draco"}, std::pair{Compression::Meshopt, "meshopt"}}) {
    SCOPED_TRACE(name);
    const std::string out = dir + "/" + stem + "-" + name + ".glb";
    ExportOptions options;
    options.compression = compression;
    write_gltf(model, out, options);
    const auto v = test::validate_gltf(out);
    EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
    const Model back = read_gltf(out);
    expect_same_targets(model, back, compression == Compression::Draco ? 2e-4f * size : 0.0f);
  }
  fs::remove_all(dir);
}

TEST(CompressedGltf, morph_targets_survive_draco_and_meshopt) {
  round_trip_targets(read_gltf_memory(morph_test::tiny_quad().glb(), "tiny.glb"), "tiny");
}

TEST(CompressedGltf, a_real_morph_model_survives_draco_and_meshopt) {
  std::string path;
  for (const std::string& p : {asset("models/AnimatedMorphSphere/AnimatedMorphSphere.gltf"),
                               std::string(DEEPCUT_SHARED_MODELS_DIR) + "/open/AnimatedMorphSphere/AnimatedMorphSphere.gltf"})
    if (path.empty() && fs::is_regular_file(p)) path = p;
  if (path.empty()) GTEST_SKIP() << "AnimatedMorphSphere is neither in assets/ nor in the shared models";
  const Model model = read_gltf(path);
  ASSERT_GT(model.meshes.at(0).target_count(), 0u);
  round_trip_targets(model, "sphere");
}

}  // namespace
}  // namespace deepcut
