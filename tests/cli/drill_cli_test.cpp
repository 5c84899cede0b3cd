// SPDX-License-Identifier: MIT
// `deepcut drill` as a user runs it: JSON report, validator-clean exports of every asset, walls,
// posed drills, misses that leave the model unchanged, bad input with exit code 2, replay.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
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

class DrillCliTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::temp_dir("drillcli"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string dir_;
};

std::string cactus() { return std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb"; }

// An axis through the middle of the model's rest-pose bounds along `axis` (0 x, 1 y, 2 z),
// from outside to outside, and a radius of `fraction` of the model size.
std::string axis_through(const Model& model, int axis, float fraction, float* radius, float offset = 0.0f) {
  const BoundingBox box = world_bounds(model, rest_pose(model));
  glm::vec3 c = 0.5f * (box.min + box.max);
  c[(axis + 1) % 3] += offset * (box.max - box.min)[(axis + 1) % 3];
  glm::vec3 a = c, b = c;
  a[axis] = box.min[axis] - 0.5f * box.diagonal();
  b[axis] = box.max[axis] + 0.5f * box.diagonal();
  *radius = fraction * box.diagonal();
  char text[256];
  std::snprintf(text, sizeof(text), "%.6g,%.6g,%.6g,%.6g,%.6g,%.6g", a.x, a.y, a.z, b.x, b.y, b.z);
  return text;
}

}  // namespace

TEST_F(DrillCliTest, drills_every_asset_and_the_exports_pass_the_validator) {
  std::vector<std::string> outputs;
  for (const auto& path : test::asset_models()) {
    SCOPED_TRACE(path);
    const Model model = read_gltf(path);
    for (int variant = 0; variant < 3; ++variant) {
      float radius = 0.0f;
      const std::string axis =
          axis_through(model, variant == 1 ? 0 : 2, variant == 2 ? 0.03f : 0.08f, &radius, 0.05f);
      const std::string out = dir_ + "/" + fs::path(path).stem().string() + std::to_string(variant) +
                              (variant == 1 ? ".gltf" : ".glb");
      std::string cmd = "drill " + test::quote(path) + " -o " + test::quote(out) + " --axis " + axis +
                        " --radius " + std::to_string(radius) + " --json";
      if (variant == 1) cmd += " --wall";
      if (variant == 2 && !model.animations.empty()) cmd += " --time 0.5";
      const auto r = test::run_cli(cmd);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      const json j = json::parse(r.out);
      for (const char* key :
           {"status", "holes", "rim_vertices", "triangles_removed", "triangles_added", "ms"})
        EXPECT_TRUE(j.contains(key)) << key;
      if (j["status"] == "ok") {
        EXPECT_EQ(j["holes"].get<std::size_t>(), j["rim_vertices"].size());
        EXPECT_GT(j["triangles_removed"].get<int>(), 0);
        const Model drilled = read_gltf(out);
        EXPECT_EQ(drilled.skins.size(), model.skins.size());
        EXPECT_EQ(drilled.animations.size(), model.animations.size());
        EXPECT_NE(drilled.extras_json.find("\"drill\""), std::string::npos)
            << "the export carries its history";
      }
      outputs.push_back(out);
    }
  }
  std::string files;
  for (const auto& o : outputs) files += " " + test::quote(o);
  const auto v = test::run_command("node " + test::quote(DEEPCUT_VALIDATOR_SCRIPT) + files);
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
}

TEST_F(DrillCliTest, through_the_cactus_gives_round_holes_and_a_wall_of_its_own_material) {
  const std::string out = dir_ + "/wall.glb";
  auto r = test::run_cli("drill " + test::quote(cactus()) + " -o " + test::quote(out) +
                         " --axis -3,2.5,0.05,3,2.5,0.05 --radius 0.3 --wall --min-rim-edges 40 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["status"], "ok");
  ASSERT_GE(j["holes"].get<int>(), 2);
  for (const auto& n : j["rim_vertices"]) EXPECT_GE(n.get<int>(), 40);
  EXPECT_GT(j["wall_triangles"].get<int>(), 0);
  const Model drilled = read_gltf(out);
  bool cut_surface = false;
  for (const auto& m : drilled.materials) cut_surface |= m.name == "Cut surface";
  EXPECT_TRUE(cut_surface);
  EXPECT_EQ(test::validate_gltf(out).exit_code, 0);
}

TEST_F(DrillCliTest, misses_leave_the_model_unchanged_and_bad_input_exits_2) {
  const std::string miss = dir_ + "/miss.glb";
  auto r = test::run_cli("drill " + test::quote(cactus()) + " -o " + test::quote(miss) +
                         " --axis 20,0,0,20,10,0 --radius 0.5 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["status"], "no_intersection");
  const ModelStats a = compute_stats(read_gltf(cactus())), b = compute_stats(read_gltf(miss));
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.welded_vertices, b.welded_vertices);
  EXPECT_EQ(a.seam_edges, b.seam_edges);
  EXPECT_EQ(read_gltf(miss).extras_json.find("\"drill\""), std::string::npos)
      << "a miss records no operation";

  const std::string bad = dir_ + "/bad.glb";
  const std::string base = "drill " + test::quote(cactus()) + " -o " + test::quote(bad);
  for (const std::string& args :
       {std::string(" --axis -3,2.5,0,3,2.5,0 --radius 0"),
        std::string(" --axis -3,2.5,0,3,2.5,0 --radius -1"), std::string(" --axis 1,2,3,1,2,3 --radius 0.2"),
        std::string(" --axis -3,nan,0,3,2.5,0 --radius 0.2"),
        std::string(" --axis -3,2.5,0,3,2.5,0 --radius nan"), std::string(" --axis -3,2.5,0 --radius 0.2"),
        std::string(" --axis -3,2.5,0,3,2.5,0"),
        std::string(" --axis -3,2.5,0,3,2.5,0 --radius 0.2 --min-rim-edges 2")}) {
    SCOPED_TRACE(args);
    r = test::run_cli(base + args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("deepcut drill: ", 0), 0u) << r.err;
    EXPECT_EQ(r.err.find("drill: drill:"), std::string::npos) << "the operation is named once: " << r.err;
    EXPECT_FALSE(fs::exists(bad));
  }
}

TEST_F(DrillCliTest, apply_replays_a_drill_history) {
  const std::string history = dir_ + "/history.json";
  std::ofstream(history) << R"({"operations": [
    {"op": "drill", "axis": [-3, 2.5, 0.05, 3, 2.5, 0.05], "radius": 0.3, "min_rim_edges": 32, "wall": true, "animation": -1},
    {"op": "drill", "axis": [0.1, 5, 0.1, 0.1, 12, 0.1], "radius": 0.2, "min_rim_edges": 32, "wall": false, "animation": -1}
  ]})";
  const std::string replayed = dir_ + "/replayed.glb";
  auto r = test::run_cli("apply " + test::quote(cactus()) + " " + test::quote(history) + " -o " +
                         test::quote(replayed) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json ops = json::parse(r.out)["operations"];
  ASSERT_EQ(ops.size(), 2u);
  EXPECT_EQ(ops[0]["status"], "ok");
  EXPECT_EQ(ops[1]["status"], "ok");
  const std::string step1 = dir_ + "/step1.glb", step2 = dir_ + "/step2.glb";
  ASSERT_EQ(test::run_cli("drill " + test::quote(cactus()) + " -o " + test::quote(step1) +
                          " --axis -3,2.5,0.05,3,2.5,0.05 --radius 0.3 --wall")
                .exit_code,
            0);
  ASSERT_EQ(test::run_cli("drill " + test::quote(step1) + " -o " + test::quote(step2) +
                          " --axis 0.1,5,0.1,0.1,12,0.1 --radius 0.2")
                .exit_code,
            0);
  const ModelStats a = compute_stats(read_gltf(replayed)), b = compute_stats(read_gltf(step2));
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.welded_vertices, b.welded_vertices);
  EXPECT_EQ(a.boundary_edges, b.boundary_edges);
  EXPECT_EQ(test::validate_gltf(replayed).exit_code, 0);

  std::ofstream(dir_ + "/broken.json") << R"({"operations": [{"op": "drill", "axis": [0, 1, 0, 0, 2, 0]}]})";
  r = test::run_cli("apply " + test::quote(cactus()) + " " + test::quote(dir_ + "/broken.json") + " -o " +
                    test::quote(dir_ + "/x.glb"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("radius"), std::string::npos) << r.err;
}

}  // namespace deepcut
