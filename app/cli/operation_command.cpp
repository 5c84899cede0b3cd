// SPDX-License-Identifier: MIT
#include "operation_command.h"

#include <chrono>
#include <iostream>
#include <optional>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/plugins/formats.h"
#include "operation_report.h"

namespace deepcut::cli {
namespace {

using nlohmann::json;

// Runs `operation()` and stores its wall time in `ms` (milliseconds). @returns its result.
template <class F>
auto run_timed(F&& operation, double& ms) {
  const auto t0 = std::chrono::steady_clock::now();
  auto result = std::forward<F>(operation)();
  ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

// A parameter as the command line names it: its flag ("min_rim_edges" -> "--min-rim-edges").
std::string flag_of(const std::string& key) {
  std::string flag = "--" + key;
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag;
}

}  // namespace

const OperationCommand* find_operation_command(const std::string& name) {
  for (const OperationCommand& command : operation_commands())
    if (command.name == name) return &command;
  return nullptr;
}

int run_operation(const OperationCommand& command, const std::vector<std::string>& argv) {
  const Args args(argv, command);
  const std::string& name = command.name;
  if (args.positionals().size() != 1) throw UsageError(name + " needs exactly one MODEL");
  if (!args.has("-o")) throw UsageError(name + " needs -o OUT (.glb or .gltf)");
  for (const OptionSpec& option : command.options)
    if (option.required && option.name != "-o" && !args.has(option.name))
      throw UsageError(name + " needs " + option.name + " " + option.value);
  const ExportOptions export_opts = export_options(args);
  Operation op;
  op.params = command.parse(args);
  check_operation(op, flag_of);  // before the model is read

  Model model = plugins::read_model(args.positionals()[0]);
  op.animation = pose_animation(args, model);
  op.time = static_cast<float>(args.number("--time", 0.0));
  const std::vector<ImportProblem> run_problems = pose_problems(args, model);
  print_problems(std::cerr, args.positionals()[0], model.import_problems);
  print_problems(std::cerr, args.positionals()[0], run_problems);
  // Tears and drills first pose the model (timed apart, as in the paper's Table 1); a cut poses
  // only the instances its plane reaches.
  double preprocess_ms = 0.0, ms = 0.0;
  std::optional<PosedModel> posed;
  if (!std::holds_alternative<CutOperation>(op.params))
    posed = run_timed(
        [&] {
          reserve_for_operations(model);
          return PosedModel::build(model, op.animation, op.time);
        },
        preprocess_ms);
  const OperationResult result =
      run_timed([&] { return posed ? apply_operation(model, op, *posed) : apply_operation(model, op); }, ms);
  json report = operation_report(model, op, result, run_problems);
  if (posed) report["preprocess_ms"] = preprocess_ms;
  if (report.contains("wall_note") && !args.flag("--json"))
    std::cerr << "deepcut: " << report["wall_note"].get<std::string>() << "\n";
  write_gltf(model, args.value("-o"), export_opts);
  if (args.flag("--json")) {
    report["ms"] = ms;
    std::cout << report.dump(2) << "\n";
  } else {
    std::cerr << "deepcut: "
              << (result.status == OpStatus::Ok ? operation_summary(result)
                                                : std::string("the ") + operation_tool(op) +
                                                      " misses the model; wrote it unchanged")
              << " -> " << args.value("-o") << "\n";
  }
  return 0;
}

}  // namespace deepcut::cli
