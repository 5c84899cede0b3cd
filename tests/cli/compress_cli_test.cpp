// SPDX-License-Identifier: MIT
// `--compress draco|meshopt` on every command that writes a model: the output names the codec in
// extensionsRequired, passes the validator and reads back with the operation's triangles; any
// other value is a usage error (exit 2, one line) before the model is read.
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/validate.h"
#include "fixtures.h"
#include "tools.h"

namespace deepcut {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json glb_json(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 20) return json();
  std::uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  return json::parse(bytes.begin() + 20, bytes.begin() + 20 + length);
}

class CompressCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir("compress-cli");
    std::ofstream(dir_ + "/history.json") << R"({"operations":[{"op":"cut","plane":[0,6,0,0,1,0.1],"cap":true}]})";
  }
  void TearDown() override { fs::remove_all(dir_); }
  // The writing commands, each with "OUT" where its output goes.
  std::vector<std::string> commands() const {
    const std::string cactus = test::quote(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
    return {"convert " + cactus + " -o OUT",
            "make-cactus -o OUT --triangles 2000",
            "cut " + cactus + " -o OUT --plane 0,5,0,0.2,1,0 --cap",
            "tear " + cactus + " -o OUT --blade-start 1.66774,7.00141,0.982109,0.125473,6.76555,1.22061 --blade-end "
                               "1.05304,5.56522,-0.803531,-0.489223,5.32936,-0.56503",
            "drill " + cactus + " -o OUT --axis 1.13198,5.89079,-0.834162,-4.11218,7.96462,4.48598 --radius 0.137452 --wall",
            "apply " + cactus + " " + test::quote(dir_ + "/history.json") + " -o OUT"};
  }
  std::string dir_;
};

std::string with_output(std::string command, const std::string& out) {
  command.replace(command.find("OUT"), 3, test::quote(out));
  return command;
}

TEST_F(CompressCli, every_writing_command_writes_draco_and_meshopt) {
  int n = 0;
  for (const auto& command : commands()) {
    for (const auto& [codec, extension] : {std::pair{"draco", "KHR_draco_mesh_compression"}, std::pair{"meshopt", "EXT_meshopt_compression"}}) {
      const std::string plain = dir_ + "/plain" + std::to_string(n) + ".glb", packed = dir_ + "/" + codec + std::to_string(n) + ".glb";
      SCOPED_TRACE(with_output(command, packed));
      const auto r0 = test::run_cli(with_output(command, plain));
      ASSERT_EQ(r0.exit_code, 0) << r0.err;
      const auto r = test::run_cli(with_output(command, packed) + " --compress " + codec);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      const json doc = glb_json(packed);
      EXPECT_NE(doc.value("extensionsRequired", json::array()).dump().find(extension), std::string::npos) << doc.dump();
      const auto v = test::validate_gltf(packed);
      EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
      EXPECT_EQ(compute_stats(read_gltf(packed)).triangles, compute_stats(read_gltf(plain)).triangles);
    }
    ++n;
  }
}

TEST_F(CompressCli, an_unknown_codec_is_a_usage_error) {
  for (const auto& command : commands()) {
    const std::string out = dir_ + "/never.glb";
    const auto r = test::run_cli(with_output(command, out) + " --compress zip");
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.err;
    EXPECT_NE(r.err.find("--compress 'zip': use none, draco or meshopt"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
}

}  // namespace
}  // namespace deepcut
