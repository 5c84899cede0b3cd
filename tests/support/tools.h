// SPDX-License-Identifier: MIT
#pragma once
// Running the deepcut CLI and the Khronos glTF-Validator from tests.

#include <string>

namespace deepcut::test {

struct RunResult {
  int exit_code = -1;
  std::string out, err;
};

/// Runs a shell command; captures stdout and stderr.
RunResult run_command(const std::string& command);

/// Runs `deepcut ARGS` (ARGS already shell-quoted).
RunResult run_cli(const std::string& args);

/// Shell-quotes one argument.
std::string quote(const std::string& s);

/// Runs the Khronos validator on a file; the result's exit code is 0 when it has no errors.
RunResult validate_gltf(const std::string& path);

/// A fresh temporary directory for one test.
std::string temp_dir(const std::string& tag);

}  // namespace deepcut::test
