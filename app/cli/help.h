// SPDX-License-Identifier: MIT
#pragma once
/// @file help.h
/// The `deepcut` commands in one table, and their help: `deepcut --help` lists every command
/// of the table (and nothing else), `deepcut CMD --help` renders that command's CommandSpec:
/// what it does, each argument's meaning and unit, the defaults and one example. main.cpp
/// dispatches through the same table, so a listed command always runs.

#include <functional>
#include <string>
#include <vector>

#include "args.h"

namespace deepcut::cli {

struct CliCommand {
  const CommandSpec* spec = nullptr;
  std::function<int(const std::vector<std::string>&)> run;
};

/// Every command, in the order `deepcut --help` lists them: the app's own, then the operation
/// commands (operation_commands()).
const std::vector<CliCommand>& cli_commands();

/// The command called `name`, or nullptr.
const CliCommand* find_cli_command(const std::string& name);

/// `deepcut --help`: every command's synopsis and summary, the MODEL formats and exit codes.
std::string usage();

/// `deepcut CMD --help`: the synopsis, summary, details, arguments (meaning, unit, default) and
/// the example of `spec`.
std::string command_help(const CommandSpec& spec);

}  // namespace deepcut::cli
