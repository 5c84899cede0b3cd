// SPDX-License-Identifier: MIT
// Nothing lost silently: every command that reads a model names each kind of repair or loss of
// reading once on stderr (naming the file, with its count) and lists it under "problems" in its
// --json report; what the file carries (asset extras and copyright, node, mesh and material
// extras, root extensions) survives `convert`, and what cannot is named.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "deepcut/core/io/gltf.h"
#include "fixtures.h"
#include "tools.h"

namespace deepcut {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

const std::string kBadDir = std::string(DEEPCUT_SOURCE_DIR) + "/tests/data/bad";
const std::string kSimpleSkin = std::string(DEEPCUT_ASSETS_DIR) + "/models/SimpleSkin/SimpleSkin.gltf";

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

json read_json(const std::string& path) {
  std::ifstream in(path);
  return json::parse(in);
}

class ProblemsCliTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::temp_dir("problems"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string dir_;
};

// A command that reads MODEL, with arguments that suit SimpleSkin's shape (a sheet in z = 0).
struct Command {
  std::string name, args;
};

std::vector<Command> reading_commands(const std::string& dir) {
  const std::string history = dir + "/history.json";
  std::ofstream(history) << R"({"operations": [{"op": "cut", "plane": [0.5, 1, 0, 0, 1, 0], "keep": "both",
                              "cap": false, "components": false, "animation": -1}]})";
  return {{"convert", "-o " + test::quote(dir + "/convert.glb")},
          {"cut", "-o " + test::quote(dir + "/cut.glb") + " --plane 0.5,1,0,0,1,0"},
          {"tear", "-o " + test::quote(dir + "/tear.glb") + " --blade-start 0.5,0.5,1,0.5,0.5,-1 --blade-end 0.5,1.5,1,0.5,1.5,-1"},
          {"drill", "-o " + test::quote(dir + "/drill.glb") + " --axis 0.5,1,-1,0.5,1,1 --radius 0.1"},
          {"apply", test::quote(history) + " -o " + test::quote(dir + "/apply.glb")},
          {"cluster", "--radius 0.3"},
          {"softbody", "--poke 0.5,1,0 --radius 0.5 --frames 3"}};
}

TEST_F(ProblemsCliTest, every_reading_command_names_each_repair_once_on_stderr_and_in_json) {
  // Two kinds of repair in one file, each in 4 vertices: influences on a joint past the skin
  // dropped, and the weights left renormalised.
  const std::string file = kBadDir + "/joint_past_skin.gltf";
  const std::vector<std::string> kinds = {"joints-past-skin", "weights-normalised"};
  for (const auto& c : reading_commands(dir_)) {
    for (const bool as_json : {false, true}) {
      const auto r = test::run_cli(c.name + " " + test::quote(file) + " " + c.args + (as_json ? " --json" : ""));
      ASSERT_EQ(r.exit_code, 0) << c.name << ": " << r.err;
      for (const auto& kind : kinds) {
        EXPECT_EQ(occurrences(r.err, " [" + kind + "]\n"), 1u) << c.name << " should name " << kind << " once: " << r.err;
        EXPECT_EQ(occurrences(r.err, "deepcut: " + file + ": "), kinds.size()) << c.name << ": " << r.err;
      }
      if (!as_json) continue;
      const json report = json::parse(r.out);
      std::vector<json> lists = {report.at("problems")};
      if (c.name == "apply") lists.push_back(report.at("operations").at(0).at("problems"));
      for (const json& problems : lists) {
        ASSERT_EQ(problems.size(), kinds.size()) << c.name << ": " << problems.dump();
        for (const auto& p : problems) {
          EXPECT_NE(std::find(kinds.begin(), kinds.end(), p.at("kind").get<std::string>()), kinds.end()) << p;
          EXPECT_EQ(p.at("count").get<std::size_t>(), 4u) << p;
          const std::string line = "deepcut: " + file + ": " + p.at("message").get<std::string>() + " [" +
                                   p.at("kind").get<std::string>() + "]\n";
          EXPECT_NE(r.err.find(line), std::string::npos) << c.name << ": stderr and JSON differ: " << r.err;
        }
      }
    }
  }
}

TEST_F(ProblemsCliTest, a_clean_file_prints_no_problem_lines) {
  for (const auto& c : reading_commands(dir_)) {
    const auto r = test::run_cli(c.name + " " + test::quote(kSimpleSkin) + " " + c.args + " --json");
    ASSERT_EQ(r.exit_code, 0) << c.name << ": " << r.err;
    EXPECT_TRUE(r.err.empty()) << c.name << ": " << r.err;
    EXPECT_TRUE(json::parse(r.out).at("problems").empty()) << c.name;
  }
}

TEST_F(ProblemsCliTest, time_on_a_model_without_animation_names_the_rest_pose) {
  // A static tube (no skin, no animation; a glTF, so every build reads it): --time can pose
  // nothing, and the user hears so once on stderr and in --json problems; the same command
  // without --time reports nothing, and a bad --animation is refused before any problem line.
  Model tube;
  tube.meshes.push_back({"tube", {}, ""});
  tube.meshes[0].primitives.emplace_back();
  tube.meshes[0].primitives[0].mesh = test::make_tube(16, 8, 0.5f, 4.0f);
  Node node;
  node.name = "tube";
  node.mesh = 0;
  tube.nodes = {node};
  tube.scenes = {{0}};
  const std::string file = dir_ + "/tube.glb";
  write_gltf(tube, file);
  const std::vector<Command> commands = {
      {"cut", "-o " + test::quote(dir_ + "/cut.glb") + " --plane 0,2,0,0,1,0"},
      {"drill", "-o " + test::quote(dir_ + "/drill.glb") + " --axis -1,2,0,1,2,0 --radius 0.1"},
      {"softbody", "--poke 0,2,0.5 --radius 0.5 --frames 2"}};
  for (const auto& c : commands) {
    for (const bool timed : {false, true}) {
      const std::string command =
          c.name + " " + test::quote(file) + " " + c.args + (timed ? " --time 1.5" : "");
      const auto r = test::run_cli(command + " --json");
      ASSERT_EQ(r.exit_code, 0) << c.name << ": " << r.err;
      const json problems = json::parse(r.out).at("problems");
      if (!timed) {
        EXPECT_TRUE(problems.empty()) << c.name << ": " << problems.dump();
        continue;
      }
      ASSERT_EQ(problems.size(), 1u) << c.name << ": " << problems.dump();
      EXPECT_EQ(problems[0].at("kind"), "time-without-animation");
      const std::string line = "deepcut: " + file +
                               ": --time 1.5: the model has no animation, so the rest pose is used"
                               " [time-without-animation]\n";
      EXPECT_EQ(occurrences(r.err, line), 1u) << c.name << ": " << r.err;
      const auto refused = test::run_cli(command + " --animation 2");
      EXPECT_EQ(refused.exit_code, 2) << c.name;
      EXPECT_EQ(occurrences(refused.err, "\n"), 1u) << c.name << ": " << refused.err;
    }
  }
}

TEST_F(ProblemsCliTest, one_line_per_kind_sums_the_places) {
  // The repair in two meshes (both drawing the same weights): one line, the counts added, both
  // places named.
  json doc = read_json(kBadDir + "/weights_sum_098.gltf");
  doc["meshes"].push_back(doc["meshes"][0]);
  doc["nodes"].push_back({{"mesh", 1}, {"skin", 0}});
  doc["scenes"][0]["nodes"].push_back(doc["nodes"].size() - 1);
  const std::string path = dir_ + "/two_meshes.gltf";
  std::ofstream(path) << doc.dump();
  const auto r = test::run_cli("convert --json " + test::quote(path) + " -o " + test::quote(dir_ + "/out.glb"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json problems = json::parse(r.out).at("problems");
  ASSERT_EQ(problems.size(), 1u) << problems.dump();
  EXPECT_EQ(problems[0].at("kind"), "weights-normalised");
  EXPECT_EQ(problems[0].at("count").get<std::size_t>(), 20u);
  EXPECT_EQ(problems[0].at("places"), json({"mesh 0 primitive 0", "mesh 1 primitive 0"}));
  EXPECT_EQ(occurrences(r.err, "\n"), 1u) << r.err;
  EXPECT_NE(r.err.find("20 vertices had weights not summing to 1 (normalised): mesh 0 primitive 0, mesh 1 primitive 0"),
            std::string::npos)
      << r.err;
}

TEST_F(ProblemsCliTest, what_the_file_carries_survives_convert_or_is_named) {
  const std::string in = kBadDir + "/extras_and_extensions.gltf";
  const json source = read_json(in);
  const std::string out = dir_ + "/out.gltf";
  const auto r = test::run_cli("convert --json " + test::quote(in) + " -o " + test::quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json back = read_json(out);
  EXPECT_EQ(back["asset"]["extras"], source["asset"]["extras"]);  // the CC-BY attribution
  EXPECT_EQ(back["asset"]["copyright"], source["asset"]["copyright"]);
  EXPECT_EQ(back["nodes"][0]["extras"], source["nodes"][0]["extras"]);
  EXPECT_EQ(back["meshes"][0]["extras"], source["meshes"][0]["extras"]);
  EXPECT_EQ(back["materials"][0]["extras"], source["materials"][0]["extras"]);
  EXPECT_EQ(back["extensions"], source["extensions"]);
  // The extension dropped everywhere is no longer declared used; the kept one is.
  EXPECT_EQ(back["extensionsUsed"], json({"EXT_deepcut_root_test"}));
  // The mesh's extension and the skin's extras are not carried through: each is named.
  const json problems = json::parse(r.out).at("problems");
  const auto find = [&](const char* kind) {
    const auto it = std::find_if(problems.begin(), problems.end(), [&](const json& p) { return p.at("kind") == kind; });
    return it == problems.end() ? json() : *it;
  };
  EXPECT_EQ(find("extension-dropped").value("places", json()), json({"EXT_deepcut_mesh_test"})) << problems.dump();
  EXPECT_EQ(find("extras-dropped").value("places", json()), json({"skin 0"})) << problems.dump();
  EXPECT_NE(r.err.find("EXT_deepcut_mesh_test"), std::string::npos) << r.err;
  const auto v = test::validate_gltf(out);
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
}

TEST_F(ProblemsCliTest, info_lists_read_repairs_and_mesh_checks_by_kind) {
  const auto r = test::run_cli("info --json " + test::quote(kBadDir + "/skin_joint_listed_twice.gltf"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << "info's report is the list: " << r.err;
  const json problems = json::parse(r.out).at("problems");
  ASSERT_FALSE(problems.empty());
  for (const auto& p : problems) {
    EXPECT_FALSE(p.at("kind").get<std::string>().empty()) << p;
    EXPECT_GT(p.at("count").get<std::size_t>(), 0u) << p;
  }
  EXPECT_EQ(problems[0].at("kind"), "skin-duplicate-joints");
  EXPECT_EQ(problems[0].at("count").get<std::size_t>(), 1u);
}

}  // namespace
}  // namespace deepcut
