// SPDX-License-Identifier: MIT
#include "tools.h"

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <sys/wait.h>

namespace deepcut::test {

std::string quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string temp_dir(const std::string& tag) {
  std::random_device rd;
  const auto dir = std::filesystem::temp_directory_path() / ("deepcut-" + tag + "-" + std::to_string(rd()));
  std::filesystem::create_directories(dir);
  return dir.string();
}

RunResult run_command(const std::string& command) {
  const std::string err_file = temp_dir("stderr") + "/err.txt";
  RunResult r;
  FILE* pipe = ::popen((command + " 2>" + quote(err_file)).c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_file);
  std::stringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  std::filesystem::remove_all(std::filesystem::path(err_file).parent_path());
  return r;
}

RunResult run_cli(const std::string& args) { return run_command(quote(DEEPCUT_CLI) + " " + args); }

RunResult validate_gltf(const std::string& path) {
  return run_command("node " + quote(DEEPCUT_VALIDATOR_SCRIPT) + " " + quote(path));
}

}  // namespace deepcut::test
