// SPDX-License-Identifier: MIT
#pragma once
// The deepcut sub-commands the app defines (the tools' own, such as cut, tear and drill, come
// from the plugins' registry: deepcut/plugins/tool_registry.h). Each returns the process exit
// code; errors propagate as deepcut::Error (input problems, exit 2) or cli::UsageError (exit 2).

#include <string>
#include <vector>

namespace deepcut::cli {

int run_info(const std::vector<std::string>& args);
int run_convert(const std::vector<std::string>& args);
int run_make_cactus(const std::vector<std::string>& args);
int run_apply(const std::vector<std::string>& args);
int run_bench(const std::vector<std::string>& args);
int run_cluster(const std::vector<std::string>& args);
int run_softbody(const std::vector<std::string>& args);

}  // namespace deepcut::cli
