// SPDX-License-Identifier: MIT
// The Poke tool's registry entry. It adds no sub-command: the headless poke is `deepcut softbody`
// (app/cli), and the interactive tool is poke_tool.cpp.
#include "deepcut/plugins/tool_registry.h"

namespace deepcut::plugins {

void describe_poke(ToolInfo& info) {
  info.id = "poke";
  info.title = "Poke";
  info.shortcut = "G";  // Blender's grab
}

}  // namespace deepcut::plugins
