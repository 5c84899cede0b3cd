// SPDX-License-Identifier: MIT
// deepcut cluster and deepcut softbody as a user runs them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tools.h"

namespace deepcut {
namespace {

using nlohmann::json;

const std::string kCactus = std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb";

std::size_t line_count(const std::string& s) { return std::count(s.begin(), s.end(), '\n'); }

json run_json(const std::string& args) {
  const test::RunResult r = test::run_cli(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.exit_code == 0 ? json::parse(r.out) : json::object();
}

TEST(SoftbodyCliTest, cluster_reports_counts_and_timing) {
  const json j = run_json("cluster " + test::quote(kCactus) + " --radius 0.73 --json");
  for (const char* key :
       {"particles", "min_vertices", "mean_vertices", "max_vertices", "uncovered_vertices", "ms"})
    ASSERT_TRUE(j.contains(key)) << key;
  EXPECT_GT(j["particles"].get<int>(), 100);
  EXPECT_EQ(j["uncovered_vertices"].get<int>(), 0);
  EXPECT_EQ(j["covered_vertices"].get<int>(), 12654);
  EXPECT_LE(j["min_vertices"].get<double>(), j["mean_vertices"].get<double>());
  EXPECT_LE(j["mean_vertices"].get<double>(), j["max_vertices"].get<double>());
  EXPECT_GE(j["ms"].get<double>(), 0.0);
  const json bigger = run_json("cluster " + test::quote(kCactus) + " --radius 1.5 --json");
  EXPECT_LT(bigger["particles"].get<int>(), j["particles"].get<int>());
}

TEST(SoftbodyCliTest, cluster_finds_the_radius_for_224_particles) {
  const json j = run_json("cluster " + test::quote(kCactus) + " --particles 224 --json");
  EXPECT_NEAR(j["particles"].get<double>(), 224.0, 3.0);
  EXPECT_GT(j["radius"].get<double>(), 0.3);
  EXPECT_LT(j["radius"].get<double>(), 1.5);
  // The radius it reports gives that count again.
  const json again = run_json("cluster " + test::quote(kCactus) + " --radius " +
                              std::to_string(j["radius"].get<double>()) + " --json");
  EXPECT_NEAR(again["particles"].get<double>(), j["particles"].get<double>(), 3.0);
}

TEST(SoftbodyCliTest, poke_rises_then_decays_to_rest) {
  const json j =
      run_json("softbody " + test::quote(kCactus) + " --poke 1.1,5,0 --radius 1.2 --frames 90 --json");
  ASSERT_TRUE(j.contains("max_displacement"));
  const auto series = j["max_displacement"].get<std::vector<double>>();
  ASSERT_EQ(series.size(), 90u);
  const double size = j["model_size"].get<double>();
  const std::size_t peak = j["peak_frame"].get<std::size_t>();
  EXPECT_GT(peak, 0u);
  EXPECT_GT(series[peak], 1e-3 * size);
  for (std::size_t f = peak + 1; f < series.size(); ++f)
    EXPECT_LE(series[f], series[f - 1] * (1.0 + 1e-5) + 1e-7 * size) << "frame " << f;
  EXPECT_LT(series.back(), 1e-4 * size);
  EXPECT_GT(j["particles_reached"].get<int>(), 0);
  EXPECT_NEAR(j["particles"].get<double>(), 224.0, 3.0);  // default: the paper's particle count
}

TEST(SoftbodyCliTest, poke_while_the_animation_plays) {
  const json j = run_json("softbody " + test::quote(kCactus) +
                          " --poke 1.1,5,0 --radius 1.2 --frames 120 --animate --time 0.5 --rho 0.8 --json");
  const auto series = j["max_displacement"].get<std::vector<double>>();
  EXPECT_TRUE(j["animated"].get<bool>());
  EXPECT_LT(series.back(), 1e-4 * j["model_size"].get<double>());
  EXPECT_GT(*std::max_element(series.begin(), series.end()), 1e-3 * j["model_size"].get<double>());
}

TEST(SoftbodyCliTest, text_output_lists_frames) {
  const test::RunResult r =
      test::run_cli("softbody " + test::quote(kCactus) + " --poke 1.1,5,0 --frames 5 --rho 0.8");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("frame    4"), std::string::npos) << r.out;
}

TEST(SoftbodyCliTest, bad_input_exits_2_with_one_line) {
  const std::string model = test::quote(kCactus);
  const std::vector<std::string> cases = {
      "cluster " + model,
      "cluster " + model + " --radius -1",
      "cluster " + model + " --radius abc",
      "cluster " + model + " --radius 0.5 --particles 10",
      "cluster " + model + " --radius 0.5 --cover 2",
      "cluster /nonexistent/model.glb --radius 0.5",
      "softbody " + model,
      "softbody " + model + " --poke 1,2",
      "softbody " + model + " --poke 1,5,0 --rho 0.8 --frames 0",
      "softbody " + model + " --poke 1,5,0 --rho 0.8 --dt -0.1",
      "softbody " + model + " --poke 100,100,100 --rho 0.8",
      "softbody " + model + " --poke 100,100,100 --rho 0.8 --impulse 1,0,0",
      "softbody " + model + " --poke 1,5,0 --rho 0.8 --mass 0"};
  for (const std::string& args : cases) {
    SCOPED_TRACE(args);
    const test::RunResult r = test::run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_EQ(line_count(r.err), 1u) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
}

}  // namespace
}  // namespace deepcut
