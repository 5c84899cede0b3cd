// SPDX-License-Identifier: MIT
#include "deepcut/plugins/registry.h"

#include "deepcut/core/errors.h"

namespace deepcut::plugins {

void Inspector::set_option(const std::string& name, const std::string& value) {
  (void)value;
  throw Error(ErrorCode::InvalidArgument, "inspector '" + id() + "' has no option '" + name + "'");
}

void InspectorRegistry::add(InspectorInfo info) {
  if (info.id.empty()) throw Error(ErrorCode::InvalidArgument, "inspector registry: an inspector has no id");
  if (!info.create)
    throw Error(ErrorCode::InvalidArgument, "inspector registry: '" + info.id + "' has no factory");
  if (find(info.id))
    throw Error(ErrorCode::InvalidArgument, "inspector registry: '" + info.id + "' is registered twice");
  infos_.push_back(std::move(info));
}

const InspectorInfo* InspectorRegistry::find(const std::string& id) const {
  for (const InspectorInfo& info : infos_)
    if (info.id == id) return &info;
  return nullptr;
}

std::unique_ptr<Inspector> InspectorRegistry::create(const std::string& id) const {
  const InspectorInfo* info = find(id);
  if (!info) throw Error(ErrorCode::InvalidArgument, "unknown inspector '" + id + "' (known: " + ids() + ")");
  return info->create();
}

std::string InspectorRegistry::ids() const {
  std::string out;
  for (const InspectorInfo& info : infos_) out += (out.empty() ? "" : ", ") + info.id;
  return out;
}

}  // namespace deepcut::plugins
