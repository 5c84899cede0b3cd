// SPDX-License-Identifier: MIT
#pragma once
/// @file operation_command.h
/// The `deepcut` sub-commands that apply one operation (`cut`, `tear`, `drill`): each is a row of
/// operation_commands() that reads its flags into the `Operation` a history file would hold;
/// run_operation does the rest for all of them (checks, pose, apply_operation, export, report),
/// so the commands, `deepcut apply` and the studio apply the same operation the same way.

#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "args.h"
#include "deepcut/core/ops/operation.h"

namespace deepcut::cli {

/// An operation command: its arguments and help (every option it accepts, -o, --time,
/// --animation and --json included; `name` is the operation's history name, "drill"), and how
/// it reads them.
struct OperationCommand : CommandSpec {
  /// The operation's parameters from the arguments. @throws UsageError for a malformed value.
  std::function<OperationParams(const Args&)> parse;
};

/// cut, tear, drill: in the order `deepcut --help` lists them.
const std::vector<OperationCommand>& operation_commands();

/// The command called `name`, or nullptr.
const OperationCommand* find_operation_command(const std::string& name);

/// Runs `command` on the arguments after its name: reads MODEL, applies the operation at the
/// pose of `--time`/`--animation` (tears and drills on a PosedModel built first, timed apart
/// as "preprocess_ms"), writes `-o OUT` (temporary file + rename), then reports: with
/// `--json`, operation_report plus "ms" on stdout; otherwise one line on stderr. @returns 0.
/// @throws UsageError or Error as the arguments, the model or the operation call for.
int run_operation(const OperationCommand& command, const std::vector<std::string>& argv);

}  // namespace deepcut::cli
