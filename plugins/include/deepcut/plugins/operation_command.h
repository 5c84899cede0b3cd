// SPDX-License-Identifier: MIT
#pragma once
/// @file operation_command.h
/// The end every operation sub-command (`deepcut cut`, `tear`, `drill`) shares: the history
/// entry, the atomic write of `-o OUT` and the report. No Qt, no VTK.

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "deepcut/core/posed_model.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/ops/op_status.h"
#include "deepcut/plugins/command_args.h"

namespace deepcut::cli {

/// Runs `operation()` and stores its wall time in `ms` (milliseconds). @returns its result.
template <class F>
auto run_timed(F&& operation, double& ms) {
  const auto t0 = std::chrono::steady_clock::now();
  auto result = std::forward<F>(operation)();
  ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

/// The operations' preprocessing, timed apart as in the paper's Table 1: gives the model room
/// to grow and builds its PosedModel (posed positions, skin frames, triangle grids) at `op`'s
/// pose. `preprocess_ms` gets the wall time.
PosedModel preprocess(Model& model, const Operation& op, double& preprocess_ms);

/// Records `op` in the model's history when it changed the model (`status` Ok), writes the
/// model to `-o` (temporary file + rename), then reports: with `--json`, `report` plus
/// "status" and "ms" on stdout; otherwise one line on stderr, `done` (or, when nothing was hit,
/// "the TOOL misses the model; wrote it unchanged") followed by " -> OUT".
void finish_operation(const Args& args, Model& model, const Operation& op, OpStatus status, double ms,
                      nlohmann::json report, const std::string& done, const std::string& tool);

}  // namespace deepcut::cli
