// SPDX-License-Identifier: MIT
// The rows of operation_commands(): each operation's flags, read into the parameters a history
// file holds (ops/operation.h). The checks that need no flag syntax are core's (check_operation).
#include <algorithm>
#include <cmath>
#include <limits>

#include "operation_command.h"

namespace deepcut::cli {
namespace {

CutOperation parse_cut(const Args& args) {
  const auto p = args.vector("--plane", 6);
  CutOperation cut;
  cut.plane = {{p[0], p[1], p[2]}, {p[3], p[4], p[5]}};
  const std::string keep = args.value("--keep", "both");
  if (keep == "both") cut.options.keep = CutKeep::Both;
  else if (keep == "positive") cut.options.keep = CutKeep::Positive;
  else if (keep == "negative") cut.options.keep = CutKeep::Negative;
  else throw UsageError("--keep must be both, positive or negative");
  cut.options.cap = args.flag("--cap");
  cut.options.split_components = args.flag("--components");
  return cut;
}

// Without --width the tear gets its blade's default width written in, so the export's history
// records the width used.
TearOperation parse_tear(const Args& args) {
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
  } else if (const float w = resolved_tear_width(tear.start, tear.end, tear.options); std::isfinite(w)) {
    tear.options.width = w;
  }
  return tear;
}

DrillOperation parse_drill(const Args& args) {
  const auto a = args.vector("--axis", 6);
  DrillOperation drill;
  drill.cylinder.a = {a[0], a[1], a[2]};
  drill.cylinder.b = {a[3], a[4], a[5]};
  drill.cylinder.radius = static_cast<float>(args.number("--radius", 0.0));
  const double edges = args.number("--min-rim-edges", drill.options.min_rim_edges);
  if (edges != std::floor(edges)) throw UsageError("--min-rim-edges must be a whole number");
  // Out of range: check_operation names the range (an int holds every value it could refuse).
  drill.options.min_rim_edges = static_cast<int>(std::clamp(edges, double(std::numeric_limits<int>::min()),
                                                            double(std::numeric_limits<int>::max())));
  drill.options.wall = args.flag("--wall");
  return drill;
}

}  // namespace

const std::vector<OperationCommand>& operation_commands() {
  static const std::vector<OperationCommand> commands = {
      {"cut",
       "cut MODEL -o OUT --plane PX,PY,PZ,NX,NY,NZ [--keep both|positive|negative] [--cap] [--components]\n"
       "    [--time T] [--animation I] [--json]",
       "cut every mesh by a plane (world space, pose at time T)",
       {"--cap", "--components"},
       {"--plane", "--keep"},
       {{"--plane", "PX,PY,PZ,NX,NY,NZ"}},
       parse_cut},
      {"tear",
       "tear MODEL -o OUT --blade-start HX,HY,HZ,TX,TY,TZ --blade-end HX,HY,HZ,TX,TY,TZ [--width W]\n"
       "    [--time T] [--animation I] [--json]",
       "tear with a scalpel swept from one blade pose to another",
       {},
       {"--blade-start", "--blade-end", "--width"},
       {{"--blade-start", "HX,HY,HZ,TX,TY,TZ"}, {"--blade-end", "HX,HY,HZ,TX,TY,TZ"}},
       parse_tear},
      {"drill",
       "drill MODEL -o OUT --axis AX,AY,AZ,BX,BY,BZ --radius R [--min-rim-edges N] [--wall]\n"
       "    [--time T] [--animation I] [--json]",
       "drill every mesh with a finite cylinder (world space, pose at time T)",
       {"--wall"},
       {"--axis", "--radius", "--min-rim-edges"},
       {{"--axis", "AX,AY,AZ,BX,BY,BZ"}, {"--radius", "R"}},
       parse_drill},
  };
  return commands;
}

}  // namespace deepcut::cli
