// SPDX-License-Identifier: MIT
#pragma once
// The deepcut sub-commands. Each returns the process exit code; errors propagate as
// deepcut::Error (input problems, exit 2) or cli::UsageError (exit 2).

#include <string>
#include <vector>

namespace deepcut {
struct Model;
}

namespace deepcut::cli {

class Args;

/// The animation an operation's `--time` refers to: `--animation I` (default 0), or -1 (rest
/// pose) when no `--time` is given. @throws UsageError for an index past the model's animations.
int pose_animation(const Args& args, const Model& model);

int run_info(const std::vector<std::string>& args);
int run_convert(const std::vector<std::string>& args);
int run_make_cactus(const std::vector<std::string>& args);
int run_cut(const std::vector<std::string>& args);
int run_tear(const std::vector<std::string>& args);
int run_drill(const std::vector<std::string>& args);
int run_apply(const std::vector<std::string>& args);
int run_bench(const std::vector<std::string>& args);
int run_cluster(const std::vector<std::string>& args);
int run_softbody(const std::vector<std::string>& args);

}  // namespace deepcut::cli
