// SPDX-License-Identifier: MIT
// The deepcut command line as a user runs it: round trips through the validator, info --json
// against known values, and malformed input that must give exit code 2 and one clear line.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/validate.h"
#include "fixtures.h"
#include "tools.h"

namespace deepcut {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

std::vector<unsigned char> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

std::size_t line_count(const std::string& s) { return std::count(s.begin(), s.end(), '\n'); }

// Posed world positions of every mesh instance at time t of animation 0 (rest pose if none).
std::vector<glm::vec3> posed(const Model& model, float t) {
  const Pose pose = model.animations.empty() ? rest_pose(model) : sample_pose(model, 0, t);
  const auto world = world_matrices(model, pose);
  std::vector<glm::vec3> out;
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    if (model.nodes[n].mesh < 0) continue;
    for (const auto& prim : model.meshes[model.nodes[n].mesh].primitives) {
      const auto p = posed_positions(model, static_cast<int>(n), prim.mesh, world, pose.weights[n]);
      out.insert(out.end(), p.begin(), p.end());
    }
  }
  return out;
}

void expect_same_model(const Model& a, const Model& b) {
  const ModelStats sa = compute_stats(a), sb = compute_stats(b);
  EXPECT_EQ(sa.triangles, sb.triangles);
  EXPECT_EQ(sa.welded_vertices, sb.welded_vertices);
  EXPECT_EQ(sa.joints, sb.joints);
  EXPECT_EQ(sa.animations, sb.animations);
  EXPECT_EQ(sa.materials, sb.materials);
  EXPECT_EQ(sa.textures, sb.textures);
  EXPECT_EQ(sa.images, sb.images);
  EXPECT_EQ(sa.seam_edges, sb.seam_edges);
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (std::size_t m = 0; m < a.meshes.size(); ++m) {
    ASSERT_EQ(a.meshes[m].primitives.size(), b.meshes[m].primitives.size());
    for (std::size_t p = 0; p < a.meshes[m].primitives.size(); ++p) {
      const auto& ma = a.meshes[m].primitives[p].mesh;
      const auto& mb = b.meshes[m].primitives[p].mesh;
      ASSERT_EQ(ma.vertex_count(), mb.vertex_count());
      ASSERT_EQ(ma.face_slots(), mb.face_slots());
      for (std::size_t v = 0; v < ma.vertex_count(); ++v)
        ASSERT_LE(glm::length(ma.positions()[v] - mb.positions()[v]), 1e-6f) << "vertex " << v;
      EXPECT_EQ(ma.faces(), mb.faces());
      if (const auto* uva = ma.corner_attrs().find<glm::vec2>(attr::kUv0)) {
        const auto* uvb = mb.corner_attrs().find<glm::vec2>(attr::kUv0);
        ASSERT_NE(uvb, nullptr);
        for (std::size_t c = 0; c < uva->size(); ++c) ASSERT_LE(glm::length((*uva)[c] - (*uvb)[c]), 1e-6f) << "corner " << c;
      }
      if (const auto* wa = ma.vertex_attrs().find<glm::vec4>(attr::kWeights0)) {
        const auto* wb = mb.vertex_attrs().find<glm::vec4>(attr::kWeights0);
        const auto& ja = ma.vertex_attrs().get<glm::u16vec4>(attr::kJoints0);
        const auto& jb = mb.vertex_attrs().get<glm::u16vec4>(attr::kJoints0);
        ASSERT_NE(wb, nullptr);
        for (std::size_t v = 0; v < wa->size(); ++v)
          for (int c = 0; c < 4; ++c) {
            ASSERT_NEAR((*wa)[v][c], (*wb)[v][c], 1e-6f) << "vertex " << v;
            if ((*wa)[v][c] > 0.0f) {
              ASSERT_EQ(ja[v][c], jb[v][c]);
            }
          }
      }
    }
  }
  const float size = sa.bounds.diagonal();
  const float duration = a.animations.empty() ? 0.0f : a.animations[0].duration();
  for (float t : {0.0f, 0.37f * duration, 0.81f * duration}) {
    const auto pa = posed(a, t), pb = posed(b, t);
    ASSERT_EQ(pa.size(), pb.size());
    float worst = 0.0f;
    for (std::size_t i = 0; i < pa.size(); ++i) worst = std::max(worst, glm::length(pa[i] - pb[i]));
    EXPECT_LE(worst, 1e-5f * size) << "posed positions differ at t = " << t;
  }
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::temp_dir("cli"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string dir_;
};

}  // namespace

TEST_F(CliTest, convert_round_trips_every_asset_through_the_validator) {
  const auto models = test::asset_models();
  ASSERT_GE(models.size(), 6u) << "assets/ should hold the cactus and the five sample models";
  for (const auto& path : models) {
    for (const char* ext : {".glb", ".gltf"}) {
      SCOPED_TRACE(path + " -> " + ext);
      const std::string out = dir_ + "/" + fs::path(path).stem().string() + ext;
      const auto r = test::run_cli("convert " + test::quote(path) + " -o " + test::quote(out));
      ASSERT_EQ(r.exit_code, 0) << r.err;
      const auto v = test::validate_gltf(out);
      EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
      expect_same_model(read_gltf(path), read_gltf(out));
    }
  }
}

TEST_F(CliTest, info_json_reports_known_counts) {
  const auto r = test::run_cli("info --json " + test::quote(std::string(DEEPCUT_ASSETS_DIR) + "/models/CesiumMan/CesiumMan.glb"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["vertices"], 3273);
  EXPECT_EQ(j["welded_vertices"], 2338);
  EXPECT_EQ(j["triangles"], 4672);
  EXPECT_EQ(j["joints"], 19);
  EXPECT_EQ(j["primitives"], 1);
  EXPECT_EQ(j["skins"], 1);
  EXPECT_EQ(j["animations"], 1);
  EXPECT_EQ(j["materials"], 1);
  EXPECT_EQ(j["boundary_edges"], 0);
  EXPECT_EQ(j["nonmanifold_edges"], 0);
  EXPECT_EQ(j["components"], 1);
  EXPECT_TRUE(j["problems"].is_array());
  EXPECT_NEAR(j["bbox"]["max"][1].get<double>(), 1.507, 1e-3);  // CesiumMan stands ~1.5 m tall

  const auto fox = json::parse(test::run_cli("info --json " + test::quote(std::string(DEEPCUT_ASSETS_DIR) + "/models/Fox/Fox.glb")).out);
  EXPECT_EQ(fox["vertices"], 1728);
  EXPECT_EQ(fox["triangles"], 576);
  EXPECT_EQ(fox["joints"], 24);
  EXPECT_EQ(fox["animations"], 3);
}

TEST_F(CliTest, info_reports_problems_in_a_dirty_file) {
  // SimpleSkin with the skin taken off its mesh node: weights that no skin uses.
  json doc = json::parse(read_bytes(std::string(DEEPCUT_ASSETS_DIR) + "/models/SimpleSkin/SimpleSkin.gltf"));
  doc["nodes"][0].erase("skin");
  const std::string path = dir_ + "/noskin.gltf";
  std::ofstream(path) << doc.dump();
  const auto r = test::run_cli("info --json " + test::quote(path));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  ASSERT_FALSE(j["problems"].empty());
  EXPECT_NE(j["problems"][0].get<std::string>().find("no node draws it with a skin"), std::string::npos);
}

TEST_F(CliTest, malformed_input_gives_exit_2_and_one_line) {
  const std::string cesium = std::string(DEEPCUT_ASSETS_DIR) + "/models/CesiumMan/CesiumMan.glb";
  const std::string simple = std::string(DEEPCUT_ASSETS_DIR) + "/models/SimpleSkin/SimpleSkin.gltf";
  const auto glb = read_bytes(cesium);
  const json simple_doc = json::parse(read_bytes(simple));

  struct Case {
    std::string name, expect;  // file name, words the message must contain
  };
  std::vector<Case> cases;
  auto add_json = [&](const std::string& name, const json& doc, const std::string& expect) {
    std::ofstream(dir_ + "/" + name) << doc.dump();
    cases.push_back({name, expect});
  };
  write_bytes(dir_ + "/truncated.glb", std::vector<unsigned char>(glb.begin(), glb.begin() + std::ptrdiff_t(glb.size() / 2)));
  cases.push_back({"truncated.glb", "truncated"});
  {
    auto bad = glb;
    bad[12] = 0xFF;  // JSON chunk length far past the end
    bad[13] = 0xFF;
    bad[14] = 0xFF;
    write_bytes(dir_ + "/chunk.glb", bad);
    cases.push_back({"chunk.glb", "past the end"});
  }
  std::ofstream(dir_ + "/badjson.gltf") << R"({"asset": {"version": "2.0"}, "meshes": [)";
  cases.push_back({"badjson.gltf", "invalid JSON"});
  {
    json doc = simple_doc;
    doc["meshes"][0]["primitives"][0]["indices"] = 42;
    add_json("accessor.gltf", doc, "indices accessor out of bounds");
  }
  {
    json doc = simple_doc;
    doc["accessors"][0]["count"] = 100000;  // indices past their bufferView
    add_json("overrun.gltf", doc, "bufferView");
  }
  {
    json doc = simple_doc;
    doc["accessors"][1]["count"] = 3;  // POSITION shrinks: indices now point past the vertices
    add_json("indices.gltf", doc, "past the 3 vertices");
  }
  {
    json doc = simple_doc;
    // A sparse override puts NaN into POSITION 0.
    const std::string nan = "AADAfwAAwH8AAMB/";  // three NaN floats, base64
    doc["buffers"].push_back({{"byteLength", 12}, {"uri", "data:application/octet-stream;base64," + nan}});
    doc["buffers"].push_back({{"byteLength", 4}, {"uri", "data:application/octet-stream;base64,AAAAAA=="}});
    const int nb = static_cast<int>(doc["buffers"].size());
    doc["bufferViews"].push_back({{"buffer", nb - 2}, {"byteLength", 12}});
    doc["bufferViews"].push_back({{"buffer", nb - 1}, {"byteLength", 4}});
    const int nv = static_cast<int>(doc["bufferViews"].size());
    doc["accessors"][1]["sparse"] = {{"count", 1},
                                     {"indices", {{"bufferView", nv - 1}, {"componentType", 5125}}},
                                     {"values", {{"bufferView", nv - 2}}}};
    add_json("nan.gltf", doc, "not finite");
  }
  {
    json doc = simple_doc;
    doc["nodes"][0]["mesh"] = 7;
    add_json("node.gltf", doc, "mesh 7");
  }
  {
    json doc = simple_doc;
    doc["buffers"][0]["uri"] = "../../../../../../etc/passwd";
    add_json("escape.gltf", doc, "outside the model's folder");
  }
  // A mesh format no build reads: named, with what this build reads, not a glTF parse error.
  std::ofstream(dir_ + "/scene.FBX", std::ios::binary) << std::string("Kaydara FBX Binary  \0\x1a\0", 23);
  cases.push_back({"scene.FBX", "cannot read .fbx files (it reads .glb .gltf"});
  cases.push_back({"missing.glb", "no such file"});

  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir_ + "/" + c.name;
    for (const std::string& cmd : {"info " + test::quote(path), "convert " + test::quote(path) + " -o " + test::quote(dir_ + "/out.glb")}) {
      const auto r = test::run_cli(cmd);
      EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.err;
      EXPECT_EQ(line_count(r.err), 1u) << r.err;
      EXPECT_NE(r.err.find(c.name), std::string::npos) << "message should name the file: " << r.err;
      EXPECT_NE(r.err.find(c.expect), std::string::npos) << "message should say '" << c.expect << "': " << r.err;
      EXPECT_FALSE(fs::exists(dir_ + "/out.glb")) << "nothing may be written on failure";
    }
  }
}

TEST_F(CliTest, usage_errors_give_exit_2) {
  EXPECT_EQ(test::run_cli("").exit_code, 2);
  EXPECT_EQ(test::run_cli("frobnicate x.glb").exit_code, 2);
  const std::string cesium = test::quote(std::string(DEEPCUT_ASSETS_DIR) + "/models/CesiumMan/CesiumMan.glb");
  EXPECT_EQ(test::run_cli("convert " + cesium).exit_code, 2);  // no -o
  const auto bad_ext = test::run_cli("convert " + cesium + " -o " + test::quote(dir_ + "/x.obj"));
  EXPECT_EQ(bad_ext.exit_code, 2);
  EXPECT_NE(bad_ext.err.find("use .glb or .gltf"), std::string::npos);
  EXPECT_EQ(test::run_cli("info --bogus " + cesium).exit_code, 2);
  EXPECT_EQ(test::run_cli("--help").exit_code, 0);
}

}  // namespace deepcut

namespace deepcut {

TEST_F(CliTest, cut_reports_pieces_and_misses_leave_the_model_unchanged) {
  const std::string cactus = std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb";
  const std::string out = dir_ + "/cut.glb";
  auto r = test::run_cli("cut " + test::quote(cactus) + " -o " + test::quote(out) + " --plane 0,5,0,0.2,1,0 --cap --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  json j = json::parse(r.out);
  EXPECT_EQ(j["status"], "ok");
  ASSERT_EQ(j["pieces"].size(), 2u);
  EXPECT_GT(j["pieces"][0]["triangles"].get<int>(), 0);
  EXPECT_GT(j["pieces"][1]["vertices"].get<int>(), 0);
  EXPECT_GT(j["intersection_points"].get<int>(), 0);
  EXPECT_TRUE(j["ms"].is_number());
  EXPECT_EQ(test::validate_gltf(out).exit_code, 0);
  const Model cut = read_gltf(out);
  EXPECT_EQ(cut.skins.size(), 1u);
  EXPECT_NE(cut.extras_json.find("deepcut_history"), std::string::npos) << "the export carries its history";

  // A plane that misses: exit 0, status no_intersection, the output is the unchanged model.
  const std::string miss = dir_ + "/miss.glb";
  r = test::run_cli("cut " + test::quote(cactus) + " -o " + test::quote(miss) + " --plane 0,50,0,0,1,0 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = json::parse(r.out);
  EXPECT_EQ(j["status"], "no_intersection");
  EXPECT_TRUE(j["pieces"].empty());
  expect_same_model(read_gltf(cactus), read_gltf(miss));

  // Zero normal: exit 2, one line, nothing written.
  const std::string bad = dir_ + "/bad.glb";
  r = test::run_cli("cut " + test::quote(cactus) + " -o " + test::quote(bad) + " --plane 0,5,0,0,0,0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(line_count(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find("normal"), std::string::npos);
  EXPECT_FALSE(fs::exists(bad));
  EXPECT_EQ(test::run_cli("cut " + test::quote(cactus) + " -o " + test::quote(bad) + " --plane 0,5,0").exit_code, 2);
  EXPECT_EQ(test::run_cli("cut " + test::quote(cactus) + " -o " + test::quote(bad) + " --plane 0,5,0,0,1,0 --keep up").exit_code, 2);
}

TEST_F(CliTest, apply_replays_a_history_like_the_single_commands) {
  const std::string cactus = std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb";
  const std::string history = dir_ + "/history.json";
  std::ofstream(history) << R"({"operations": [
    {"op": "cut", "plane": [0, 6, 0, 0, 1, 0.1], "keep": "both", "cap": true, "animation": -1},
    {"op": "cut", "plane": [0.5, 0, 0, 1, 0, 0], "keep": "negative", "cap": false, "time": 1.5}
  ]})";
  const std::string replayed = dir_ + "/replayed.glb";
  auto r = test::run_cli("apply " + test::quote(cactus) + " " + test::quote(history) + " -o " + test::quote(replayed) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["operations"].size(), 2u);
  // The same two cuts one by one through `deepcut cut`.
  const std::string step1 = dir_ + "/step1.glb", step2 = dir_ + "/step2.glb";
  ASSERT_EQ(test::run_cli("cut " + test::quote(cactus) + " -o " + test::quote(step1) + " --plane 0,6,0,0,1,0.1 --cap").exit_code, 0);
  ASSERT_EQ(test::run_cli("cut " + test::quote(step1) + " -o " + test::quote(step2) +
                          " --plane 0.5,0,0,1,0,0 --keep negative --time 1.5").exit_code, 0);
  expect_same_model(read_gltf(replayed), read_gltf(step2));
  EXPECT_EQ(test::validate_gltf(replayed).exit_code, 0);
  // The export carries the history; replaying it on the original gives the same model again.
  const std::string again = dir_ + "/again.glb";
  const Model replayed_model = read_gltf(replayed);
  std::ofstream(dir_ + "/embedded.json") << json::parse(replayed_model.extras_json)["deepcut_history"].dump();
  ASSERT_EQ(test::run_cli("apply " + test::quote(cactus) + " " + test::quote(dir_ + "/embedded.json") + " -o " + test::quote(again)).exit_code, 0);
  expect_same_model(read_gltf(again), replayed_model);

  // Wrong types, unknown keys and bad poses: exit 2, naming the file and the operation.
  for (const char* op : {R"({"op": "cut", "plane": [0, 5, 0, 0, 1, 0], "cap": "yes"})",
                                R"({"op": "cut", "plane": [0, 5, 0, 0, 1, 0], "components": 1})",
                                R"({"op": "cut", "plane": [0, 5, 0, 0, 1, 0], "keep": 5})",
                                R"({"op": 5, "plane": [0, 5, 0, 0, 1, 0]})",
                                R"({"op": "cut", "plane": [0, 5, 0, 0, 1, 0], "cpa": true})",
                                R"({"op": "cut", "plane": [0, 5, 0, 0, 1, 0], "animation": 7})",
                                R"({"op": "cut", "plane": [0, 5, 0, 0, 0, 0]})"}) {
    SCOPED_TRACE(op);
    std::ofstream(dir_ + "/typed.json") << std::string(R"({"operations": [)") + op + "]}";
    r = test::run_cli("apply " + test::quote(cactus) + " " + test::quote(dir_ + "/typed.json") + " -o " + test::quote(dir_ + "/x.glb"));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("typed.json"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("operation 0"), std::string::npos) << r.err;
  }
  std::ofstream(dir_ + "/broken.json") << R"({"operations": [{"op": "cut", "plane": [0, 1]}]})";
  r = test::run_cli("apply " + test::quote(cactus) + " " + test::quote(dir_ + "/broken.json") + " -o " + test::quote(dir_ + "/x.glb"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("broken.json"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("operation 0"), std::string::npos) << r.err;
}

}  // namespace deepcut
