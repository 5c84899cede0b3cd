// SPDX-License-Identifier: MIT
#pragma once
/// @file inspector_registry.h
/// The studio's inspectors (inspector.h): each plugin folder `plugins/NAME/` defines
/// `void deepcut::plugins::register_NAME(InspectorRegistry&)`, and builtin_inspectors() calls them
/// in the order plugins/src/builtin_studio.cpp lists them. Adding an inspector is adding its
/// folder, its sources in plugins/CMakeLists.txt and its line there.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "deepcut/plugins/inspector.h"
#include "deepcut/plugins/registry.h"

namespace deepcut::plugins {

struct InspectorInfo {
  std::string id;     ///< command-line name, unique
  std::string title;  ///< menu text
  std::function<std::unique_ptr<Inspector>()> create;
};

inline const std::string& registry_id(const InspectorInfo& info) { return info.id; }
/// @throws Error{InvalidArgument} if the id is empty or taken, or `create` is empty.
void check_entry(const InspectorInfo& info, const std::vector<InspectorInfo>& taken);

using InspectorRegistry = Registry<InspectorInfo>;

/// The inspectors built into this program, in list order.
const InspectorRegistry& builtin_inspectors();

}  // namespace deepcut::plugins
