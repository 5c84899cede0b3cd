// SPDX-License-Identifier: MIT
#pragma once
/// @file tool_registry.h
/// The studio's operation tools (tool.h): tool bar order, titles, shortcuts and factories. Each
/// tool plugin folder `plugins/NAME/` defines `std::unique_ptr<Tool> create_NAME_tool()`, and
/// builtin_tools() lists them in plugins/src/builtin_studio.cpp, one line per tool. Adding a tool
/// is adding its folder, its sources in plugins/CMakeLists.txt and its line there. (The command
/// line's `cut`, `tear` and `drill` are app/cli's: they need no tool.)

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "deepcut/plugins/registry.h"

namespace deepcut::plugins {

class Tool;

struct ToolInfo {
  std::string id;        ///< history and tool name ("cut"), unique
  std::string title;     ///< tool bar text ("Plane")
  std::string shortcut;  ///< key sequence that chooses the tool ("" none), e.g. "P"
  std::function<std::unique_ptr<Tool>()> create;  ///< the interactive tool
};

inline const std::string& registry_id(const ToolInfo& info) { return info.id; }
/// @throws Error{InvalidArgument} if the id is empty or taken, or `create` is empty.
void check_entry(const ToolInfo& info, const std::vector<ToolInfo>& taken);

using ToolRegistry = Registry<ToolInfo>;

/// The tools built into the studio, in tool bar order.
const ToolRegistry& builtin_tools();

}  // namespace deepcut::plugins
