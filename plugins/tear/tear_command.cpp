// SPDX-License-Identifier: MIT
// The Scalpel tool's command line: deepcut tear (the studio side is tear_tool.cpp).
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "deepcut/plugins/formats.h"
#include "deepcut/plugins/operation_command.h"
#include "deepcut/plugins/tool_registry.h"

namespace deepcut::cli {
namespace {

int run_tear(const std::vector<std::string>& argv) {
  const Args args(argv, {"--json"},
                  {"-o", "--blade-start", "--blade-end", "--width", "--time", "--animation"});
  if (args.positionals().size() != 1) throw UsageError("tear needs exactly one MODEL");
  if (!args.has("-o")) throw UsageError("tear needs -o OUT (.glb or .gltf)");
  if (!args.has("--blade-start")) throw UsageError("tear needs --blade-start HX,HY,HZ,TX,TY,TZ");
  if (!args.has("--blade-end")) throw UsageError("tear needs --blade-end HX,HY,HZ,TX,TY,TZ");
  const auto s = args.vector("--blade-start", 6);
  const auto e = args.vector("--blade-end", 6);
  const auto check_range = [](const char* name, const std::vector<double>& values) {
    for (const double v : values)
      if (std::abs(v) > double(std::numeric_limits<float>::max()))
        throw UsageError(std::string(name) + ": a coordinate beyond 3.4e38 overflows single precision");
  };
  check_range("--blade-start", s);
  check_range("--blade-end", e);
  TearOperation tear;
  tear.start = {glm::vec3(s[0], s[1], s[2]), glm::vec3(s[3], s[4], s[5])};
  tear.end = {glm::vec3(e[0], e[1], e[2]), glm::vec3(e[3], e[4], e[5])};
  if (args.has("--width")) {
    const double w = args.number("--width", 0.0);
    if (w < 0.0) throw UsageError("--width must be >= 0");
    tear.options.width = static_cast<float>(w);
  }
  swept_quad_triangles(tear.start, tear.end);  // a degenerate blade fails before the model is read

  Model model = plugins::read_model(args.positionals()[0]);
  Operation op;
  op.animation = pose_animation(args, model);
  op.time = static_cast<float>(args.number("--time", 0.0));
  double preprocess_ms = 0.0, ms = 0.0;
  PosedModel index = preprocess(model, op, preprocess_ms);
  const ModelTearResult r = run_timed(
      [&] { return tear_model(model, index, tear.start, tear.end, tear.options, op.animation, op.time); }, ms);
  tear.options.width = r.width;  // the history records the width used
  op.params = tear;
  finish_operation(args, model, op, r.status, ms,
                   {{"tear_vertices", r.tear_vertices},
                    {"intersection_points", r.intersection_points},
                    {"slits", r.slits},
                    {"width", r.width},
                    {"opening", r.opening},
                    {"preprocess_ms", preprocess_ms}},
                   "tore " + count_of(r.slits, "slit", "slits") + ", " +
                       count_of(r.tear_vertices, "tear vertex", "tear vertices") + ", opening " +
                       std::to_string(r.opening) + " (asked " + std::to_string(r.width) + ")",
                   "blade");
  return 0;
}

}  // namespace
}  // namespace deepcut::cli

namespace deepcut::plugins {

void describe_tear(ToolInfo& info) {
  info.id = "tear";
  info.title = "Scalpel";
  info.shortcut = "T";
  info.commands.push_back(
      {"tear",
       "tear MODEL -o OUT --blade-start HX,HY,HZ,TX,TY,TZ --blade-end HX,HY,HZ,TX,TY,TZ [--width W]\n"
       "    [--time T] [--animation I] [--json]",
       "tear with a scalpel swept from one blade pose to another", cli::run_tear});
}

}  // namespace deepcut::plugins
