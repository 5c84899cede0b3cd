// SPDX-License-Identifier: MIT
// deepcut bench: runs the benchmark suite (build/bin/deepcut_bench, built beside deepcut).
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "commands.h"
#include "args.h"
#include "deepcut/core/errors.h"

namespace deepcut::cli {

const CommandSpec& bench_command() {
  static const CommandSpec spec = with_synopsis(
      {"bench",
       {},
       "the benchmark suite, with VTK peers measured in the same run",
       "Runs deepcut_bench, built beside deepcut (it needs VTK and Google Benchmark: scripts/build.sh): "
       "the operations and the soft body on generated cactus models, with VTK's filters as peers measured "
       "in the same run (docs/BENCHMARKS.md). It takes no MODEL: it generates its own inputs.",
       {{"--quick", "", "skip the cases of about 1M triangles", "", false, false},
        {"--studio", "", "run the studio benchmark instead (deepcut_studio_bench, built beside deepcut: open, "
                         "apply, undo and redo to the render call, an unchanged re-render, memory per "
                         "operation; under xvfb-run when there is no display)", "", false, false},
        {"--benchmark_filter", "REGEX", "run only the benchmarks whose name matches REGEX (Google Benchmark's "
                                        "filter)", "every benchmark", false, false},
        json_option("the results")},
       "deepcut bench --quick",
       {}});
  return spec;
}

int run_bench(const std::vector<std::string>& argv) {
  const Args args(argv, bench_command());
  if (!args.positionals().empty()) throw UsageError("bench takes no MODEL: it generates its own inputs");
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const bool studio = args.flag("--studio");
  const auto bench = (ec ? std::filesystem::path(".") : self.parent_path()) /
                     (studio ? "deepcut_studio_bench" : "deepcut_bench");
  if (!std::filesystem::exists(bench))
    throw Error(ErrorCode::Io, bench.string() + ": not built (it needs VTK and Google Benchmark: run scripts/build.sh)");
  std::vector<std::string> forward = {bench.string()};
  const char* display = std::getenv("DISPLAY");
  if (studio && (!display || !*display))  // the studio needs a display: a virtual one
    forward = {"xvfb-run", "-a", "-s", "-screen 0 1600x1000x24", bench.string()};
  if (args.flag("--json")) forward.push_back("--json");
  if (args.flag("--quick")) forward.push_back("--quick");
  if (args.has("--benchmark_filter") && !studio) forward.push_back("--benchmark_filter=" + args.value("--benchmark_filter"));
  std::vector<char*> raw;
  for (auto& s : forward) raw.push_back(s.data());
  raw.push_back(nullptr);
  ::execvp(raw[0], raw.data());
  throw Error(ErrorCode::Io, std::string(raw[0]) + ": could not start");
}

}  // namespace deepcut::cli
