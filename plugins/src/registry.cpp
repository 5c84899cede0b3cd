// SPDX-License-Identifier: MIT
#include "deepcut/plugins/inspector_registry.h"

#include "deepcut/core/errors.h"

namespace deepcut::plugins {

void Inspector::set_option(const std::string& name, const std::string& value) {
  (void)value;
  throw Error(ErrorCode::InvalidArgument, "inspector '" + id() + "' has no option '" + name + "'");
}

void check_entry(const InspectorInfo& info, const std::vector<InspectorInfo>& /*taken*/) {
  if (!info.create) throw Error(ErrorCode::InvalidArgument, "inspector registry: '" + info.id + "' has no factory");
}

}  // namespace deepcut::plugins
