// SPDX-License-Identifier: MIT
// three.js, a second real client, poses what deepcut writes as the project does: every asset,
// its round trips, cuts, tears and drills made at a pose, and a replayed history, at two moments
// of the first clip (the rest pose without one), vertex for vertex within 1e-5 of the model size
// (see tests/support/three_client.h). Skipped when node or three.js is not installed.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/skinning.h"
#include "fixtures.h"
#include "three_client.h"
#include "tools.h"

namespace deepcut {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

std::string numbers(std::initializer_list<glm::vec3> points) {
  std::ostringstream s;
  s.precision(7);
  const char* sep = "";
  for (const glm::vec3& p : points) {
    s << sep << p.x << "," << p.y << "," << p.z;
    sep = ",";
  }
  return s.str();
}

// The pose the operations are made at: 0.37 of the first clip, or the rest pose.
struct EditPose {
  int animation = -1;
  float time = 0.0f;
  std::string args() const {
    return animation < 0 ? std::string() : " --animation 0 --time " + std::to_string(time);
  }
};

EditPose edit_pose(const Model& model) {
  if (model.animations.empty()) return {};
  return {0, 0.37f * model.animations[0].duration()};
}

// A tube along +y skinned to a chain of eight joints with eight influences on every vertex
// (JOINTS_1/WEIGHTS_1), the chain bending in a clip: three.js skins with four influences, and
// pose_three.mjs must add the other four.
Model make_eight_influence_model() {
  Model model = test::make_skinned_tube_model();
  model.nodes.resize(3);  // the tube, the root joint, the scene root
  model.skins[0].joints = {1};
  model.skins[0].inverse_bind_matrices = {glm::mat4(1.0f)};
  model.animations[0].channels.clear();
  int parent = 1;
  for (int j = 1; j < 8; ++j) {
    Node joint;
    joint.name = "joint" + std::to_string(j);
    joint.translation = {0.0f, 0.5f, 0.0f};
    model.nodes[std::size_t(parent)].children = {int(model.nodes.size())};
    parent = int(model.nodes.size());
    model.nodes.push_back(joint);
    model.skins[0].joints.push_back(parent);
    model.skins[0].inverse_bind_matrices.push_back(glm::translate(glm::mat4(1.0f), glm::vec3(0, -0.5f * float(j), 0)));
    model.animations[0].channels.push_back({0, parent, AnimationPath::Rotation});
  }
  SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  auto& j0 = mesh.vertex_attrs().get<glm::u16vec4>(attr::kJoints0);
  auto& w0 = mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0);
  auto& j1 = mesh.vertex_attrs().add<glm::u16vec4>(attr::kJoints1);
  auto& w1 = mesh.vertex_attrs().add<glm::vec4>(attr::kWeights1);
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    float w[8], sum = 0.0f;
    for (int j = 0; j < 8; ++j) sum += w[j] = 1.0f / (1.0f + std::abs(mesh.positions()[v].y - 0.5f * float(j)));
    j0[v] = {0, 1, 2, 3};
    j1[v] = {4, 5, 6, 7};
    w0[v] = glm::vec4(w[0], w[1], w[2], w[3]) / sum;
    w1[v] = glm::vec4(w[4], w[5], w[6], w[7]) / sum;
  }
  return model;
}

// Every node that draws morph targets has a non-zero weight at `pose` (edits are made at an
// expression, not at the base shape).
void expect_morphs_at_non_zero_weights(const Model& model, const Pose& pose) {
  for (std::size_t node = 0; node < model.nodes.size(); ++node) {
    const int mesh = model.nodes[node].mesh;
    if (mesh < 0 || model.meshes[std::size_t(mesh)].target_count() == 0) continue;
    const auto& w = pose.weights[node];
    EXPECT_TRUE(std::any_of(w.begin(), w.end(), [](float x) { return x != 0.0f; })) << "node " << node;
  }
}

class ThreeClientTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string why = test::three_unavailable();
    if (!why.empty()) GTEST_SKIP() << why;
    dir_ = test::temp_dir("three");
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }

  // Runs deepcut ARGS writing `out` (in the test's folder); returns its path.
  std::string write(const std::string& out, const std::string& args) {
    const std::string path = dir_ + "/" + out;
    const auto r = test::run_cli(args + " -o " + test::quote(path) + " --json");
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
    if (r.exit_code == 0) {
      EXPECT_EQ(json::parse(r.out).value("status", "ok"), "ok") << args << "\n" << r.out;
    }
    return path;
  }

  // Cut, tear and drill of `path` at its edit pose, aimed at the posed model.
  void edit_at_a_pose(const std::string& path, std::vector<std::string>& out) {
    const Model model = read_gltf(path);
    const EditPose at = edit_pose(model);
    const Pose pose = at.animation < 0 ? rest_pose(model) : sample_pose(model, 0, at.time);
    if (at.animation >= 0) expect_morphs_at_non_zero_weights(model, pose);
    const BoundingBox box = world_bounds(model, pose);
    const glm::vec3 c = 0.5f * (box.min + box.max);
    const float s = box.diagonal();
    const std::string stem = fs::path(path).stem().string(), in = test::quote(path);
    out.push_back(write(stem + "-cut.glb", "cut " + in + " --plane " + numbers({c, {0.3f, 1.0f, 0.2f}}) + " --cap" + at.args()));
    out.push_back(write(stem + "-drill.gltf", "drill " + in + " --axis " +
                                                  numbers({c + glm::vec3(0, 0, -s), c + glm::vec3(0, 0, s)}) +
                                                  " --radius " + std::to_string(0.05f * s) + " --wall" + at.args()));
    // A blade across the posed surface through the triangle centroid nearest the middle, along
    // the triangle's normal, swept along a skew direction (not along the model's axes, so not in
    // the plane of a box's side).
    const PosedModel posed = PosedModel::build(model, at.animation, at.time, PoseDetail::Positions);
    glm::vec3 p = c, n(0, 0, 1);
    float best = 1e30f;
    for (const auto& [key, inst] : posed.instances()) {
      const SurfaceMesh& mesh = model.meshes[std::size_t(inst.mesh)].primitives[std::size_t(key.second)].mesh;
      for (const Triangle& t : mesh.faces()) {
        const glm::vec3 a = inst.posed[t[0].index], b = inst.posed[t[1].index], d = inst.posed[t[2].index];
        const glm::vec3 q = (a + b + d) / 3.0f, normal = glm::cross(b - a, d - a);
        if (glm::length(normal) > 0.0f && glm::length(q - c) < best) best = glm::length(q - c), p = q, n = glm::normalize(normal);
      }
    }
    const glm::vec3 skew_a = glm::normalize(glm::vec3(0.83f, 0.31f, 0.47f)), skew_b = glm::normalize(glm::vec3(-0.31f, 0.47f, 0.83f));
    const glm::vec3 t = glm::normalize(glm::cross(n, std::abs(glm::dot(n, skew_a)) < 0.7f ? skew_a : skew_b));
    const float h = 0.05f * s;
    out.push_back(write(stem + "-tear.glb", "tear " + in + " --blade-start " + numbers({p + h * n - h * t, p - h * n - h * t}) +
                                                " --blade-end " + numbers({p + h * n + h * t, p - h * n + h * t}) +
                                                " --width " + std::to_string(0.01f * s) + at.args()));
  }

  // three.js and the project pose every file alike at two moments of its first clip. The first
  // `inputs` files are inputs rather than exports (see ThreePoseRequest::unit_rotations).
  void expect_three_agrees(const std::vector<std::string>& files, std::size_t inputs = 0) {
    std::vector<test::ThreePoseRequest> requests;
    for (const auto& f : files) requests.push_back(test::two_times_of_first_clip(f, requests.size() < inputs));
    const auto results = test::compare_with_three(requests);
    ASSERT_EQ(results.size(), files.size());
    for (const auto& r : results) {
      SCOPED_TRACE(r.file);
      EXPECT_GT(r.corners, 0u) << "nothing was compared";
      for (const auto& p : r.problems) ADD_FAILURE() << p;
    }
  }

  std::string dir_;
};

}  // namespace

TEST_F(ThreeClientTest, every_asset_and_its_round_trips_pose_alike) {
  std::vector<std::string> files = test::asset_models();
  ASSERT_GE(files.size(), 6u);
  for (const auto& path : test::asset_models())
    for (const char* ext : {".glb", ".gltf"})
      files.push_back(write(fs::path(path).stem().string() + ext, "convert " + test::quote(path)));
  expect_three_agrees(files, test::asset_models().size());
}

TEST_F(ThreeClientTest, cuts_tears_and_drills_at_a_pose_and_a_replayed_history_pose_alike) {
  std::vector<std::string> files;
  for (const auto& path : test::asset_models()) edit_at_a_pose(path, files);
  const std::string cactus = std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb";
  const std::string history = dir_ + "/history.json";
  std::ofstream(history) << R"({"operations": [
    {"op": "cut", "plane": [0, 6, 0, 0, 1, 0.1], "keep": "both", "cap": true, "time": 1.5},
    {"op": "drill", "axis": [-3, 4, 0, 3, 4, 0], "radius": 0.3, "wall": true, "time": 2.5},
    {"op": "cut", "plane": [0.5, 0, 0, 1, 0, 0], "keep": "negative", "cap": false, "animation": -1}
  ]})";
  files.push_back(write("history.glb", "apply " + test::quote(cactus) + " " + test::quote(history)));
  expect_three_agrees(files);
}

// The shared sample models in ../shared/models/open beside the checkout (or the folder the
// environment's DEEPCUT_SHARED_MODELS_DIR names), each as read and after `convert`.
TEST_F(ThreeClientTest, the_shared_open_models_and_their_round_trips_pose_alike) {
  const char* env = std::getenv("DEEPCUT_SHARED_MODELS_DIR");
  const fs::path open = fs::path(env && *env ? env : DEEPCUT_SHARED_MODELS_DIR) / "open";
  if (!fs::exists(open)) GTEST_SKIP() << open << " does not exist (the shared models sit beside the checkout)";
  std::vector<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(open)) {
    const auto ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".glb" && ext != ".gltf")) continue;
    files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  const std::size_t originals = files.size();
  for (std::size_t i = 0; i < originals; ++i)
    files.push_back(write(fs::path(files[i]).stem().string() + "-convert.glb", "convert " + test::quote(files[i])));
  expect_three_agrees(files, originals);
}

TEST_F(ThreeClientTest, a_skinned_and_morphing_rig_and_its_edits_at_a_morphed_pose_pose_alike) {
  const std::string path = dir_ + "/morph-tube.glb";
  write_gltf(test::make_morph_tube_model(), path);
  const Model back = read_gltf(path);
  ASSERT_EQ(back.meshes.at(0).target_count(), 2u) << "the export keeps the morph targets";
  ASSERT_FALSE(back.animations.empty());
  EXPECT_EQ(test::validate_gltf(path).exit_code, 0);
  std::vector<std::string> files = {path};
  edit_at_a_pose(path, files);
  expect_three_agrees(files);
}

TEST_F(ThreeClientTest, eight_influences_per_vertex_pose_alike) {
  const std::string path = dir_ + "/eight.glb";
  write_gltf(make_eight_influence_model(), path);
  const Model back = read_gltf(path);
  ASSERT_NE(back.meshes[0].primitives[0].mesh.vertex_attrs().find<glm::vec4>(attr::kWeights1), nullptr)
      << "the export keeps the second set of influences";
  EXPECT_EQ(test::validate_gltf(path).exit_code, 0);
  expect_three_agrees({path});
}

}  // namespace deepcut
