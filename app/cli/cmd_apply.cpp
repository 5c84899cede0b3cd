// SPDX-License-Identifier: MIT
// deepcut apply: replay a history file.
#include <chrono>
#include <fstream>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "operation_report.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/ops/operation.h"
#include "args.h"
#include "deepcut/plugins/formats.h"
#include "session.h"

namespace deepcut::cli {

using nlohmann::json;

const CommandSpec& apply_command() {
  static const CommandSpec spec = with_synopsis(
      {"apply",
       {{"MODEL", "the model to edit: a rigged .glb/.gltf, or a static .obj/.ply/.stl/.off mesh"},
        {"HISTORY.json", "the operations, {\"operations\": [{\"op\": \"cut\", ...}, ...]}, in the format every "
                         "export carries under deepcut_history in its root extras (docs/cli.md, History files)"}},
       "replay a list of operations",
       "Applies the operations of HISTORY.json to MODEL in order, each at its own pose (its time and "
       "animation), exactly as the operation commands and the studio apply them, and writes the result. "
       "Because every export records the operations that made it, a file's history replays on the "
       "original model. A malformed operation exits 2 naming the file and the operation's index.",
       [] {
         std::vector<OptionSpec> o = output_options();
         o.push_back(json_option("operations (each operation's report, as its own command prints it, without "
                                 "timings) and ms"));
         return o;
       }(),
       "deepcut apply assets/cactus.glb edits.json -o edited.glb",
       {}});
  return spec;
}

int run_apply(const std::vector<std::string>& argv) {
  const Args args(argv, apply_command());
  if (args.positionals().size() != 2) throw UsageError("apply needs MODEL and HISTORY.json");
  if (!args.has("-o")) throw UsageError("apply needs -o OUT (.glb or .gltf)");
  const std::string history_path = args.positionals()[1];
  std::ifstream in(history_path);
  if (!in) throw Error(ErrorCode::Io, history_path + ": cannot open history file");
  std::stringstream ss;
  ss << in.rdbuf();
  History history;
  try {
    history = parse_history(ss.str());
  } catch (const Error& e) {
    throw Error(e.code(), history_path + ": " + e.what());
  }
  Model model = plugins::read_model(args.positionals()[0]);
  print_problems(std::cerr, args.positionals()[0], model.import_problems);
  const json problems = problems_report(model.import_problems);
  reserve_for_operations(model);
  // A session without undo steps: one copy of the model that every operation edits, and one
  // posed model (built by the first drill or tear, rebuilt when an operation's pose differs or
  // after a cut), followed from each operation's edit log. Errors name the history file and the
  // operation, whatever the operation complained about.
  session::Session session(session::Session::Undo::None);
  session.open(std::make_shared<const Model>(std::move(model)));
  json reports = json::array();
  const auto t0 = std::chrono::steady_clock::now();
  session.apply_history(history, history_path, [&](std::size_t i, const Model& after, const session::Applied& applied) {
    const Operation& op = history.operations[i];
    json report = operation_report(after, op, applied.result);
    report["op"] = operation_name(op);
    reports.push_back(std::move(report));
  });
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  write_gltf(*session.current(), args.value("-o"));
  if (args.flag("--json")) {
    std::cout << json{{"operations", reports}, {"problems", problems}, {"ms", ms}}.dump(2) << "\n";
  } else {
    std::cerr << "deepcut: applied " << count_of(history.operations.size(), "operation", "operations") << " -> "
              << args.value("-o") << "\n";
  }
  return 0;
}

}  // namespace deepcut::cli
