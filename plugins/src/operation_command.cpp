// SPDX-License-Identifier: MIT
#include "deepcut/plugins/operation_command.h"

#include <iostream>

#include "deepcut/core/io/gltf.h"

namespace deepcut::cli {

PosedModel preprocess(Model& model, const Operation& op, double& preprocess_ms) {
  return run_timed(
      [&] {
        reserve_for_operations(model);
        return PosedModel::build(model, op.animation, op.time);
      },
      preprocess_ms);
}

void finish_operation(const Args& args, Model& model, const Operation& op, OpStatus status, double ms,
                      nlohmann::json report, const std::string& done, const std::string& tool) {
  if (status == OpStatus::Ok) record_operation(model, op);
  write_gltf(model, args.value("-o"));
  if (args.flag("--json")) {
    report["status"] = to_string(status);
    report["ms"] = ms;
    std::cout << report.dump(2) << "\n";
  } else {
    std::cerr << "deepcut: "
              << (status == OpStatus::Ok ? done : "the " + tool + " misses the model; wrote it unchanged") << " -> "
              << args.value("-o") << "\n";
  }
}

}  // namespace deepcut::cli
