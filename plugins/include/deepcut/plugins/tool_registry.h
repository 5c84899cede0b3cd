// SPDX-License-Identifier: MIT
#pragma once
/// @file tool_registry.h
/// The one list of operation tools, shared by the studio (tool bar, panels, previews) and the
/// `deepcut` command line (sub-commands, `--help`). Each tool plugin folder `plugins/NAME/`
/// defines, in a file without Qt or VTK,
///   `void deepcut::plugins::describe_NAME(ToolInfo& info)`
/// (id, title, the command-line sub-commands it adds) and, with the studio,
///   `std::unique_ptr<Tool> deepcut::plugins::create_NAME_tool()`
/// (tool.h). The build list `DEEPCUT_TOOL_PLUGINS` in `plugins/CMakeLists.txt` generates
/// `builtin_tools()`, which calls them in that order; the command line gets the same list without
/// the interactive factories. Adding a tool is adding its folder and its name to that list.
/// No Qt, no VTK.

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace deepcut::plugins {

class Tool;

/// A `deepcut` sub-command a tool adds. `run` gets the arguments after the command name and
/// returns the exit code; it reports errors by throwing cli::UsageError (exit 2) or
/// deepcut::Error (exit 2 for input errors, 1 otherwise), as the app's own commands do.
struct ToolCommand {
  std::string name;      ///< the sub-command ("cut"), unique across the program
  std::string synopsis;  ///< its usage after "deepcut ", lines joined by '\n' (continuations indented)
  std::string summary;   ///< one line: what it does
  std::function<int(const std::vector<std::string>&)> run;
};

struct ToolInfo {
  std::string id;                      ///< history and tool name ("cut"), unique
  std::string title;                   ///< tool bar text ("Plane")
  std::vector<ToolCommand> commands;   ///< command-line sub-commands (may be empty)
  /// The interactive tool; empty in programs built without the studio (the command line).
  std::function<std::unique_ptr<Tool>()> create;
  std::string shortcut;                ///< key sequence that chooses the tool ("" none), e.g. "P"
};

class ToolRegistry {
 public:
  /// @throws Error{InvalidArgument} if the id is empty or taken, or a command is unnamed, has no
  ///         `run`, or is named twice. (An entry without commands is a studio-only tool; in the
  ///         command line's list it has neither.)
  void add(ToolInfo info);
  const std::vector<ToolInfo>& list() const { return infos_; }
  /// @returns the entry with `id`, or nullptr.
  const ToolInfo* find(const std::string& id) const;
  /// @returns the sub-command `name` of any entry, or nullptr.
  const ToolCommand* find_command(const std::string& name) const;
  /// The ids, comma separated ("cut, tear, drill").
  std::string ids() const;

 private:
  std::vector<ToolInfo> infos_;
};

/// The tools built into this program, in build-list order.
const ToolRegistry& builtin_tools();

}  // namespace deepcut::plugins
