// SPDX-License-Identifier: MIT
// What a tester met running the command line as a new user: each case is one report, run the way
// the user ran it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/validate.h"
#include "tools.h"

namespace deepcut {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

const std::string kCactus = std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb";

std::size_t line_count(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

class UserReportsTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::temp_dir("userreports"); }
  void TearDown() override { fs::remove_all(dir_); }
  // Expects exit 2 with exactly one stderr line containing `words`, and nothing on stdout.
  static void expect_refused(const test::RunResult& r, const std::string& words) {
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(words), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("inf"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("null"), std::string::npos) << r.out;
  }
  std::string dir_;
};

// The boundary a tear leaves: its edge count once the file is read back (and welded).
std::size_t boundary_edges(const std::string& path) { return compute_stats(read_gltf(path)).boundary_edges; }

}  // namespace

TEST_F(UserReportsTest, a_huge_tear_width_opens_every_layer_and_reports_the_opening_achieved) {
  // A blade swept up through the whole cactus (trunk and arms: seven slits).
  const std::string blade = " --blade-start -3,6,0,3,6,0 --blade-end -3,6.5,0,3,6.5,0 --json";
  std::size_t edges[2] = {0, 0};
  const char* widths[2] = {"0.05", "1e9"};
  for (int i = 0; i < 2; ++i) {
    const std::string out = dir_ + "/tear" + std::to_string(i) + ".glb";
    const auto r = test::run_cli("tear " + test::quote(kCactus) + " -o " + test::quote(out) + blade + " --width " +
                                 widths[i]);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const json j = json::parse(r.out);
    ASSERT_EQ(j["status"], "ok");
    ASSERT_TRUE(j.contains("opening")) << r.out;
    const double width = j["width"].get<double>(), opening = j["opening"].get<double>();
    EXPECT_FLOAT_EQ(static_cast<float>(width), std::stof(widths[i]));
    EXPECT_GT(opening, 0.0);
    EXPECT_LE(opening, width * (1.0 + 1e-5));
    edges[i] = boundary_edges(out);
  }
  EXPECT_GT(edges[0], 0u);
  EXPECT_EQ(edges[1], edges[0]) << "the width changed which slits open";
}

TEST_F(UserReportsTest, tear_names_the_blade_whose_coordinates_are_out_of_scale) {
  const std::string out = dir_ + "/t.glb";
  auto r = test::run_cli("tear " + test::quote(kCactus) + " -o " + test::quote(out) +
                         " --blade-start 0,1e30,2,0,7,0 --blade-end 0,4,2,0,4,0");
  expect_refused(r, "the start blade");
  EXPECT_EQ(r.err.find("zero length"), std::string::npos) << r.err;
  r = test::run_cli("tear " + test::quote(kCactus) + " -o " + test::quote(out) +
                    " --blade-start 0,4,2,0,4,0 --blade-end 0,1e39,2,0,7,0");
  expect_refused(r, "--blade-end");
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(UserReportsTest, softbody_refuses_a_speed_whose_displacement_overflows) {
  const auto r = test::run_cli("softbody " + test::quote(kCactus) + " --poke 1.1,5,0 --frames 5 --rho 0.8 --speed 1e30 --json");
  expect_refused(r, "--speed");
}

TEST_F(UserReportsTest, animation_indices_are_whole_numbers_from_minus_one) {
  const std::string out = dir_ + "/t.glb";
  const std::string tear = "tear " + test::quote(kCactus) + " -o " + test::quote(out) +
                           " --blade-start 0,6,2,0,6,-2 --blade-end 1,6,2,1,6,-2 --time 0.5 --animation ";
  expect_refused(test::run_cli(tear + "-2"), "--animation -2");
  expect_refused(test::run_cli(tear + "0.5"), "not a whole number");
  expect_refused(test::run_cli("drill " + test::quote(kCactus) + " -o " + test::quote(out) +
                               " --axis 0,5,3,0,5,-3 --radius 0.3 --animation 0.5"),
                 "not a whole number");
  EXPECT_EQ(test::run_cli(tear + "-1").exit_code, 0);  // -1: the rest pose
  const auto r = test::run_cli("softbody " + test::quote(kCactus) +
                               " --poke 1.1,5,0 --frames 5 --rho 0.8 --animate --animation -1");
  expect_refused(r, "rest pose");
  EXPECT_EQ(r.err.find("no animation"), std::string::npos) << r.err;
}

TEST_F(UserReportsTest, a_drill_that_would_remove_a_whole_instance_is_refused) {
  const std::string out = dir_ + "/d.glb";
  const auto r = test::run_cli("drill " + test::quote(kCactus) + " -o " + test::quote(out) +
                               " --axis 0,-10,0,0,20,0 --radius 100");
  expect_refused(r, "removes every triangle");
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(UserReportsTest, info_lists_a_scene_without_mesh_as_a_problem) {
  Model model = read_gltf(kCactus);
  for (auto& n : model.nodes) n.mesh = -1, n.skin = -1;
  model.meshes.clear();
  const std::string path = dir_ + "/empty.glb";
  write_gltf(model, path);
  const auto r = test::run_cli("info " + test::quote(path) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json problems = json::parse(r.out)["problems"];
  EXPECT_TRUE(std::any_of(problems.begin(), problems.end(), [](const json& p) { return p["message"] == "the scene has no mesh"; })) << problems;
}

TEST_F(UserReportsTest, help_after_a_command_prints_that_commands_usage) {
  const auto r = test::run_cli("tear --help");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("usage: deepcut tear MODEL", 0), 0u) << r.out;
  EXPECT_EQ(r.out.find("drill"), std::string::npos) << r.out;
  EXPECT_EQ(test::run_cli("drill -o x.glb -h").out.rfind("usage: deepcut drill MODEL", 0), 0u);
}

TEST_F(UserReportsTest, a_wall_that_cannot_be_built_is_reported_not_silently_left_out) {
  // Along the trunk's axis, the end planes inside the cactus: every hole of the closed model is
  // walled (bottom disks included), so there is nothing to report.
  const std::string walled = dir_ + "/w.glb";
  const auto r = test::run_cli("drill " + test::quote(kCactus) + " -o " + test::quote(walled) +
                               " --axis 0,-1,0,0,12,0 --radius 0.3 --wall --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_GT(j["wall_triangles"].get<std::size_t>(), 0u) << r.out;
  EXPECT_EQ(j["unwalled_holes"].get<std::size_t>(), 0u) << r.out;
  EXPECT_FALSE(j.contains("wall_note")) << r.out;
  // An open hole first, then a walled drill overlapping it: the new rims join the old opening,
  // which no wall can close; the output says how many holes and why.
  const std::string open = dir_ + "/open.glb";
  ASSERT_EQ(test::run_cli("drill " + test::quote(kCactus) + " -o " + test::quote(open) +
                          " --axis -3,5,0,3,5,0 --radius 0.4")
                .exit_code,
            0);
  const auto again = test::run_cli("drill " + test::quote(open) + " -o " + test::quote(dir_ + "/w2.glb") +
                                   " --axis -3,5.3,0,3,5.3,0 --radius 0.4 --wall --json");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const json k = json::parse(again.out);
  ASSERT_GT(k["unwalled_holes"].get<std::size_t>(), 0u) << again.out;
  ASSERT_TRUE(k.contains("wall_note")) << again.out;
  EXPECT_NE(k["wall_note"].get<std::string>().find("no wall for"), std::string::npos);
  EXPECT_NE(k["wall_note"].get<std::string>().find("boundary the model already had"), std::string::npos);
}

TEST_F(UserReportsTest, counts_in_messages_agree_with_their_nouns) {
  const auto r = test::run_cli("tear " + test::quote(kCactus) + " -o " + test::quote(dir_ + "/t.glb") +
                               " --blade-start 0,6,2,0,6,-2 --blade-end 1,6,2,1,6,-2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("tore 1 slit,"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("(s)"), std::string::npos) << r.err;
}

TEST_F(UserReportsTest, make_cactus_wants_a_whole_triangle_count) {
  const std::string out = dir_ + "/c.glb";
  expect_refused(test::run_cli("make-cactus -o " + test::quote(out) + " --triangles 1500.7"), "--triangles");
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace deepcut
