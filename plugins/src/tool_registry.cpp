// SPDX-License-Identifier: MIT
#include "deepcut/plugins/tool_registry.h"

#include "deepcut/core/errors.h"

namespace deepcut::plugins {

void ToolRegistry::add(ToolInfo info) {
  if (info.id.empty()) throw Error(ErrorCode::InvalidArgument, "tool registry: a tool has no id");
  if (find(info.id)) throw Error(ErrorCode::InvalidArgument, "tool registry: '" + info.id + "' is registered twice");
  for (const ToolCommand& command : info.commands) {
    if (command.name.empty() || !command.run)
      throw Error(ErrorCode::InvalidArgument, "tool registry: '" + info.id + "' has a command without a name or a run");
    if (find_command(command.name))
      throw Error(ErrorCode::InvalidArgument, "tool registry: command '" + command.name + "' is registered twice");
  }
  infos_.push_back(std::move(info));
}

const ToolInfo* ToolRegistry::find(const std::string& id) const {
  for (const ToolInfo& info : infos_)
    if (info.id == id) return &info;
  return nullptr;
}

const ToolCommand* ToolRegistry::find_command(const std::string& name) const {
  for (const ToolInfo& info : infos_)
    for (const ToolCommand& command : info.commands)
      if (command.name == name) return &command;
  return nullptr;
}

std::string ToolRegistry::ids() const {
  std::string out;
  for (const ToolInfo& info : infos_) out += (out.empty() ? "" : ", ") + info.id;
  return out;
}

}  // namespace deepcut::plugins
