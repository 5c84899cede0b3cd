// SPDX-License-Identifier: MIT
#include "deepcut/plugins/tool_registry.h"

#include "deepcut/core/errors.h"

namespace deepcut::plugins {

void check_entry(const ToolInfo& info, const std::vector<ToolInfo>& /*taken*/) {
  if (!info.create) throw Error(ErrorCode::InvalidArgument, "tool registry: '" + info.id + "' has no factory");
}

}  // namespace deepcut::plugins
