// SPDX-License-Identifier: MIT
// One operation path: the same operation through its command (`deepcut cut|tear|drill`), through
// `deepcut apply` and through apply_operation in-process writes the same bytes and reports the
// same keys and values (timings aside), and a drill that would swallow an instance is refused by
// all three with the same message.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/plugins/formats.h"
#include "operation_report.h"
#include "tools.h"

namespace deepcut {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

const std::string kCactus = std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb";

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

json without(json report, std::initializer_list<const char*> keys) {
  for (const char* key : keys) report.erase(key);
  return report;
}

// A blade through the cactus trunk's front wall (from radius 1.6 to 0.7) at height y, angle phi.
Blade blade(float y, float phi) {
  const float s = std::sin(phi), c = std::cos(phi);
  return {{1.6f * s, y, 1.6f * c}, {0.7f * s, y, 0.7f * c}};
}

std::string flag_text(const Blade& b) {
  std::ostringstream o;
  o.precision(9);
  o << b.handle.x << "," << b.handle.y << "," << b.handle.z << "," << b.tip.x << "," << b.tip.y << "," << b.tip.z;
  return o.str();
}

struct Case {
  std::string name;
  std::string command;  ///< `deepcut` arguments after MODEL -o OUT
  Operation op;         ///< the same operation, as a history holds it
};

std::vector<Case> cases() {
  std::vector<Case> out;
  {
    CutOperation cut;
    cut.plane = {{0.0f, 6.0f, 0.0f}, {0.0f, 1.0f, 0.1f}};
    cut.options.cap = true;
    out.push_back({"cut_capped", "cut --plane 0,6,0,0,1,0.1 --cap", {cut, -1, 0.0f}});
    cut.plane = {{0.5f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}};
    cut.options.cap = false;
    cut.options.keep = CutKeep::Negative;
    cut.options.split_components = true;
    out.push_back({"cut_posed", "cut --plane 0.5,0,0,1,0,0 --keep negative --components --time 1.5", {cut, 0, 1.5f}});
  }
  {
    TearOperation tear;
    tear.start = blade(3.0f, -0.2f);
    tear.end = blade(4.5f, 0.2f);
    tear.options.width = 0.05f;
    out.push_back({"tear", "tear --blade-start " + flag_text(tear.start) + " --blade-end " + flag_text(tear.end) +
                               " --width 0.05",
                   {tear, -1, 0.0f}});
  }
  {
    DrillOperation drill;
    drill.cylinder = {{-3.0f, 2.5f, 0.05f}, {3.0f, 2.5f, 0.05f}, 0.3f};
    drill.options.wall = true;
    out.push_back({"drill_walled", "drill --axis -3,2.5,0.05,3,2.5,0.05 --radius 0.3 --wall", {drill, -1, 0.0f}});
    drill.cylinder = {{0.1f, 5.0f, 0.1f}, {0.1f, 12.0f, 0.1f}, 0.2f};
    drill.options.wall = false;
    drill.options.min_rim_edges = 12;
    out.push_back({"drill_posed", "drill --axis 0.1,5,0.1,0.1,12,0.1 --radius 0.2 --min-rim-edges 12 --time 0.5",
                   {drill, 0, 0.5f}});
  }
  return out;
}

class OnePathTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::temp_dir("onepath"); }
  void TearDown() override { fs::remove_all(dir_); }

  // `deepcut apply` of a history holding only `op`.
  test::RunResult apply_cli(const Operation& op, const std::string& out) {
    const std::string history = dir_ + "/history.json";
    std::ofstream(history) << history_to_json(History{{op}});
    return test::run_cli("apply " + test::quote(kCactus) + " " + test::quote(history) + " -o " + test::quote(out) +
                         " --json");
  }

  std::string dir_;
};

TEST_F(OnePathTest, a_command_apply_and_apply_operation_write_the_same_bytes_and_report) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const std::string a = dir_ + "/" + c.name + "_command.glb", b = dir_ + "/" + c.name + "_apply.glb",
                      d = dir_ + "/" + c.name + "_library.glb";
    const std::string name = c.command.substr(0, c.command.find(' '));
    const auto command = test::run_cli(name + " " + test::quote(kCactus) + " -o " + test::quote(a) +
                                       c.command.substr(name.size()) + " --json");
    ASSERT_EQ(command.exit_code, 0) << command.err;
    const auto applied = apply_cli(c.op, b);
    ASSERT_EQ(applied.exit_code, 0) << applied.err;

    Model model = plugins::read_model(kCactus);
    reserve_for_operations(model);
    PosedModel posed;
    const OperationResult result = apply_operation(model, c.op, posed);
    ASSERT_EQ(result.status, OpStatus::Ok);
    write_gltf(model, d);
    const json library = cli::operation_report(model, c.op, result);

    const json from_command = without(json::parse(command.out), {"ms", "preprocess_ms"});
    const json from_apply = json::parse(applied.out)["operations"][0];
    EXPECT_EQ(from_apply["op"], name);
    EXPECT_EQ(from_command, without(from_apply, {"op"}));
    EXPECT_EQ(from_command, library);
    const std::string bytes = file_bytes(a);
    EXPECT_FALSE(bytes.empty());
    EXPECT_TRUE(bytes == file_bytes(b)) << "deepcut apply wrote other bytes than deepcut " << name;
    EXPECT_TRUE(bytes == file_bytes(d)) << "apply_operation wrote other bytes than deepcut " << name;
    EXPECT_EQ(model_history(read_gltf(a)).operations.size(), 1u);
  }
}

TEST_F(OnePathTest, a_drill_that_swallows_an_instance_is_refused_by_every_front_end_alike) {
  DrillOperation drill;
  drill.cylinder = {{0.0f, -10.0f, 0.0f}, {0.0f, 20.0f, 0.0f}, 100.0f};
  const Operation op{drill, -1, 0.0f};
  const std::string a = dir_ + "/command.glb", b = dir_ + "/apply.glb";
  const auto command =
      test::run_cli("drill " + test::quote(kCactus) + " -o " + test::quote(a) + " --axis 0,-10,0,0,20,0 --radius 100");
  const auto applied = apply_cli(op, b);
  EXPECT_EQ(command.exit_code, 2);
  EXPECT_EQ(applied.exit_code, 2);
  EXPECT_FALSE(fs::exists(a));
  EXPECT_FALSE(fs::exists(b));

  Model model = plugins::read_model(kCactus);
  std::string message;
  try {
    apply_operation(model, op);
    FAIL() << "apply_operation drilled away a whole instance";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    message = e.what();
  }
  EXPECT_NE(message.find("removes every triangle of node"), std::string::npos) << message;
  EXPECT_EQ(command.err, "deepcut drill: " + message + "\n");
  EXPECT_NE(applied.err.find(": operation 0: " + message + "\n"), std::string::npos) << applied.err;

  // A front end that wants the node emptied says so in the options; the rule is then off.
  Model emptied = plugins::read_model(kCactus);
  Operation allowed = op;
  std::get<DrillOperation>(allowed.params).options.refuse_swallowed_instances = false;
  const OperationResult result = apply_operation(emptied, allowed);
  EXPECT_EQ(result.status, OpStatus::Ok);
}

}  // namespace
}  // namespace deepcut
