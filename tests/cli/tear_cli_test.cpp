// SPDX-License-Identifier: MIT
// `deepcut tear` and tear operations in `deepcut apply`, as a user runs them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/validate.h"
#include "tools.h"

namespace deepcut {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

class TearCliTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::temp_dir("tearcli"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string dir_;
  const std::string cactus_ = std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb";
};

std::size_t line_count(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

// A blade through the trunk's front wall (from radius 1.6 to 0.7) at height y, angle phi.
std::string blade(double y, double phi) {
  const double s = std::sin(phi), c = std::cos(phi);
  std::ostringstream o;
  o << 1.6 * s << "," << y << "," << 1.6 * c << "," << 0.7 * s << "," << y << "," << 0.7 * c;
  return o.str();
}

}  // namespace

TEST_F(TearCliTest, tear_reports_the_slit_and_records_it) {
  const std::string out = dir_ + "/tear.glb";
  auto r = test::run_cli("tear " + test::quote(cactus_) + " -o " + test::quote(out) + " --blade-start " +
                         blade(3.0, -0.2) + " --blade-end " + blade(4.5, 0.2) + " --width 0.05 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["status"], "ok");
  EXPECT_GT(j["tear_vertices"].get<int>(), 4);
  EXPECT_GT(j["intersection_points"].get<int>(), 2);
  EXPECT_EQ(j["slits"].get<int>(), 1);
  EXPECT_NEAR(j["width"].get<double>(), 0.05, 1e-6);
  EXPECT_TRUE(j["ms"].is_number());
  EXPECT_EQ(test::validate_gltf(out).exit_code, 0);
  const Model torn = read_gltf(out);
  const ModelStats stats = compute_stats(torn), before = compute_stats(read_gltf(cactus_));
  EXPECT_GT(stats.boundary_edges, before.boundary_edges) << "the slit is open";
  EXPECT_EQ(stats.skins, 1u);
  EXPECT_EQ(stats.animations, before.animations);
  const History h = model_history(torn);
  ASSERT_EQ(h.operations.size(), 1u);
  ASSERT_TRUE(std::holds_alternative<TearOperation>(h.operations[0].params));
  EXPECT_NEAR(std::get<TearOperation>(h.operations[0].params).options.width, 0.05f, 1e-6f);
}

TEST_F(TearCliTest, a_blade_that_misses_leaves_the_model_unchanged) {
  const std::string out = dir_ + "/miss.glb";
  const auto r =
      test::run_cli("tear " + test::quote(cactus_) + " -o " + test::quote(out) + " --blade-start " +
                    blade(30.0, 0.0) + " --blade-end " + blade(31.0, 0.0) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["status"], "no_intersection");
  EXPECT_EQ(j["tear_vertices"].get<int>(), 0);
  const ModelStats a = compute_stats(read_gltf(cactus_)), b = compute_stats(read_gltf(out));
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.welded_vertices, b.welded_vertices);
  EXPECT_EQ(a.boundary_edges, b.boundary_edges);
  EXPECT_TRUE(model_history(read_gltf(out)).operations.empty());
}

TEST_F(TearCliTest, degenerate_blades_exit_2_with_one_line_and_write_nothing) {
  const std::string out = dir_ + "/bad.glb";
  const std::string base = "tear " + test::quote(cactus_) + " -o " + test::quote(out);
  for (const std::string& args :
       {std::string(" --blade-start 0,3,1.6,0,3,1.6 --blade-end " + blade(4.0, 0.0)),
        std::string(" --blade-start " + blade(3.0, 0.0) + " --blade-end " + blade(3.0, 0.0)),
        std::string(" --blade-start " + blade(3.0, 0.0) + " --blade-end " + blade(4.0, 0.0) + " --width -1"),
        std::string(" --blade-start 0,3,1.6 --blade-end " + blade(4.0, 0.0)),
        std::string(" --blade-start " + blade(3.0, 0.0))}) {
    SCOPED_TRACE(args);
    const auto r = test::run_cli(base + args);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
  const auto r = test::run_cli(base + " --blade-start 0,3,1.6,0,3,1.6 --blade-end " + blade(4.0, 0.0));
  EXPECT_NE(r.err.find("zero length"), std::string::npos) << r.err;
  const auto same =
      test::run_cli(base + " --blade-start " + blade(3.0, 0.0) + " --blade-end " + blade(3.0, 0.0));
  EXPECT_NE(same.err.find("identical"), std::string::npos) << same.err;
}

TEST_F(TearCliTest, apply_replays_consecutive_strokes_like_the_single_commands) {
  // Five strokes along a curve, then one across them.
  std::vector<std::pair<std::string, std::string>> strokes;
  for (int k = 0; k < 5; ++k)
    strokes.emplace_back(blade(3.0 + 0.3 * k, -0.3 + 0.12 * k), blade(3.3 + 0.3 * k, -0.18 + 0.12 * k));
  strokes.emplace_back(blade(3.45, -0.35), blade(3.45, 0.25));
  json ops = json::array();
  for (const auto& [s, e] : strokes) {
    auto nums = [](const std::string& v) {
      json a = json::array();
      std::stringstream ss(v);
      std::string item;
      while (std::getline(ss, item, ',')) a.push_back(std::stod(item));
      return a;
    };
    ops.push_back({{"op", "tear"},
                   {"blade_start", nums(s)},
                   {"blade_end", nums(e)},
                   {"width", 0.03},
                   {"animation", -1}});
  }
  const std::string history = dir_ + "/history.json";
  std::ofstream(history) << json{{"operations", ops}}.dump();
  const std::string replayed = dir_ + "/replayed.glb";
  auto r = test::run_cli("apply " + test::quote(cactus_) + " " + test::quote(history) + " -o " +
                         test::quote(replayed) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json reports = json::parse(r.out)["operations"];
  ASSERT_EQ(reports.size(), strokes.size());
  for (const auto& rep : reports) {
    EXPECT_EQ(rep["op"], "tear");
    EXPECT_EQ(rep["status"], "ok");
  }
  EXPECT_EQ(test::validate_gltf(replayed).exit_code, 0);
  // The same strokes one by one.
  std::string in = cactus_;
  for (std::size_t k = 0; k < strokes.size(); ++k) {
    const std::string out = dir_ + "/step" + std::to_string(k) + ".glb";
    ASSERT_EQ(test::run_cli("tear " + test::quote(in) + " -o " + test::quote(out) + " --blade-start " +
                            strokes[k].first + " --blade-end " + strokes[k].second + " --width 0.03")
                  .exit_code,
              0);
    in = out;
  }
  const ModelStats a = compute_stats(read_gltf(replayed)), b = compute_stats(read_gltf(in));
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.welded_vertices, b.welded_vertices);
  EXPECT_EQ(a.boundary_edges, b.boundary_edges);
  EXPECT_EQ(model_history(read_gltf(replayed)).operations.size(), strokes.size());

  std::ofstream(dir_ + "/broken.json")
      << R"({"operations": [{"op": "tear", "blade_start": [0, 1, 2], "blade_end": [0, 1, 2, 3, 4, 5]}]})";
  r = test::run_cli("apply " + test::quote(cactus_) + " " + test::quote(dir_ + "/broken.json") + " -o " +
                    test::quote(dir_ + "/x.glb"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("blade_start"), std::string::npos) << r.err;
}

}  // namespace deepcut
