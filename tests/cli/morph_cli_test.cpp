// SPDX-License-Identifier: MIT
// `deepcut info` lists each mesh's morph targets (count, names, default weights) and every
// animation channel on morph weights, in text and in --json; `convert` keeps them.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "../core/gltf_morph_fixtures.h"
#include "tools.h"

namespace deepcut {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

const std::string kCube = std::string(DEEPCUT_ASSETS_DIR) + "/models/AnimatedMorphCube/AnimatedMorphCube.gltf";

}  // namespace

TEST(MorphCliTest, info_lists_targets_and_weight_channels) {
  const auto r = test::run_cli("info --json " + test::quote(kCube));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json info = json::parse(r.out);
  ASSERT_EQ(info["morph_targets"].size(), 1u);
  EXPECT_EQ(info["morph_targets"][0]["name"], "Cube");
  EXPECT_EQ(info["morph_targets"][0]["targets"], 2);
  EXPECT_EQ(info["morph_targets"][0]["weights"], json::array({0.0, 0.0}));
  ASSERT_EQ(info["weight_channels"].size(), 1u);
  EXPECT_EQ(info["weight_channels"][0]["animation_name"], "Square");
  EXPECT_EQ(info["weight_channels"][0]["node"], 0);
  EXPECT_EQ(info["weight_channels"][0]["targets"], 2);
  EXPECT_EQ(info["weight_channels"][0]["keys"], 127);
  EXPECT_EQ(info["weight_channels"][0]["interpolation"], "linear");

  const auto text = test::run_cli("info " + test::quote(kCube));
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("morph targets: mesh 0 'Cube' 2, weights [0.0,0.0]"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("weight channel: 'Square' -> node 0 'AnimatedMorphCube' (2 targets, 127 keys, linear)"),
            std::string::npos)
      << text.out;

  // A model without targets lists none (and its text shows no morph line).
  const auto plain = test::run_cli("info --json " + test::quote(std::string(DEEPCUT_ASSETS_DIR) + "/models/Fox/Fox.glb"));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_TRUE(json::parse(plain.out)["morph_targets"].empty());
  EXPECT_TRUE(json::parse(plain.out)["weight_channels"].empty());
}

TEST(MorphCliTest, convert_keeps_target_names_and_every_interpolation) {
  const std::string dir = test::temp_dir("morph-cli");
  const auto bytes = morph_test::tiny_quad().glb();
  std::ofstream(dir + "/quad.glb", std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  const auto c = test::run_cli("convert " + test::quote(dir + "/quad.glb") + " -o " + test::quote(dir + "/out.gltf"));
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const auto v = test::validate_gltf(dir + "/out.gltf");
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
  const json info = json::parse(test::run_cli("info --json " + test::quote(dir + "/out.gltf")).out);
  EXPECT_EQ(info["morph_targets"][0]["names"], json::array({"lift", "tilt"}));
  EXPECT_EQ(info["morph_targets"][0]["weights"], json::array({0.25, 0.75}));
  ASSERT_EQ(info["weight_channels"].size(), 2u);
  EXPECT_EQ(info["weight_channels"][0]["interpolation"], "cubic spline");
  EXPECT_EQ(info["weight_channels"][1]["interpolation"], "step");
  const auto text = test::run_cli("info " + test::quote(dir + "/out.gltf"));
  EXPECT_NE(text.out.find("morph targets: mesh 0 '' 2 (lift, tilt), weights [0.25,0.75]"), std::string::npos) << text.out;
  fs::remove_all(dir);
}

}  // namespace deepcut
