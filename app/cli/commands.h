// SPDX-License-Identifier: MIT
#pragma once
// The deepcut sub-commands besides the operation commands (cut, tear and drill, which one runner
// applies: operation_command.h). Each returns the process exit code; errors propagate as
// deepcut::Error (input problems, exit 2) or cli::UsageError (exit 2).

#include <string>
#include <vector>

#include "args.h"

namespace deepcut::cli {

// Each command's arguments and help (help.h renders them), next to its code.
const CommandSpec& info_command();
const CommandSpec& convert_command();
const CommandSpec& make_cactus_command();
const CommandSpec& apply_command();
const CommandSpec& bench_command();
const CommandSpec& cluster_command();
const CommandSpec& softbody_command();

int run_info(const std::vector<std::string>& args);
int run_convert(const std::vector<std::string>& args);
int run_make_cactus(const std::vector<std::string>& args);
int run_apply(const std::vector<std::string>& args);
int run_bench(const std::vector<std::string>& args);
int run_cluster(const std::vector<std::string>& args);
int run_softbody(const std::vector<std::string>& args);

}  // namespace deepcut::cli
