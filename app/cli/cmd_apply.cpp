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

namespace deepcut::cli {

using nlohmann::json;

int run_apply(const std::vector<std::string>& argv) {
  const Args args(argv, {"--json"}, {"-o"});
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
  json reports = json::array();
  const auto t0 = std::chrono::steady_clock::now();
  // One preprocessing for the whole run (built by the first drill or tear, rebuilt when an
  // operation's pose differs or after a cut), followed from each operation's edit log.
  PosedModel index;
  reserve_for_operations(model);
  for (std::size_t i = 0; i < history.operations.size(); ++i) {
    try {
      const Operation& op = history.operations[i];
      const OperationResult result = apply_operation(model, op, index);
      json report = operation_report(model, op, result);
      report["op"] = operation_name(op);
      reports.push_back(std::move(report));
    } catch (const Error& e) {
      // Name the history file and the operation, whatever the operation complained about.
      throw Error(e.code(), history_path + ": operation " + std::to_string(i) + ": " + e.what());
    }
  }
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  write_gltf(model, args.value("-o"));
  if (args.flag("--json")) {
    std::cout << json{{"operations", reports}, {"ms", ms}}.dump(2) << "\n";
  } else {
    std::cerr << "deepcut: applied " << count_of(history.operations.size(), "operation", "operations") << " -> "
              << args.value("-o") << "\n";
  }
  return 0;
}

}  // namespace deepcut::cli
