// SPDX-License-Identifier: MIT
#pragma once
/// @file registry.h
/// The list of inspector plugins. Each plugin folder `plugins/NAME/` defines
/// `void deepcut::plugins::register_NAME(InspectorRegistry&)`; the build list in
/// `plugins/CMakeLists.txt` generates `builtin_inspectors()`, which calls them in that order.
/// Adding an inspector is adding a folder and its name to that list.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "deepcut/plugins/inspector.h"

namespace deepcut::plugins {

struct InspectorInfo {
  std::string id;     ///< command-line name, unique
  std::string title;  ///< menu text
  std::function<std::unique_ptr<Inspector>()> create;
};

class InspectorRegistry {
 public:
  /// @throws Error{InvalidArgument} if the id is empty, taken, or `create` is empty.
  void add(InspectorInfo info);
  const std::vector<InspectorInfo>& list() const { return infos_; }
  /// @returns the entry with `id`, or nullptr.
  const InspectorInfo* find(const std::string& id) const;
  /// @throws Error{InvalidArgument} naming the known ids if `id` is unknown.
  std::unique_ptr<Inspector> create(const std::string& id) const;
  /// The ids, comma separated ("weights, adjacency").
  std::string ids() const;

 private:
  std::vector<InspectorInfo> infos_;
};

/// The inspectors built into this program, in build-list order.
const InspectorRegistry& builtin_inspectors();

}  // namespace deepcut::plugins
