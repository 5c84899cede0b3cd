// SPDX-License-Identifier: MIT
#pragma once
/// @file registry.h
/// One list of plugins of a kind, in the order they were added: model formats (formats.h),
/// operation tools (tool_registry.h) and inspectors (inspector_registry.h) are each a
/// `Registry<Info>`. The built-in lists are written out by hand in plugins/src/builtin.cpp and
/// plugins/src/builtin_studio.cpp, one line per plugin. No Qt, no VTK.
///
/// An Info type provides, beside its declaration (found by argument-dependent lookup):
///   `const std::string& registry_id(const Info&)`: the entry's unique, non-empty name;
///   `void check_entry(const Info&, const std::vector<Info>& taken)` (or `Info&`, to normalise
///   the entry): its kind's own rules, throwing Error{InvalidArgument} (e.g. a missing
///   factory, an extension read already). `add` then refuses an empty or taken id.

#include <string>
#include <vector>

#include "deepcut/core/errors.h"

namespace deepcut::plugins {

/// @throws Error{InvalidArgument} when `id` is empty or `taken`.
void check_registry_id(const std::string& id, bool taken);

template <class Info>
class Registry {
 public:
  /// @throws Error{InvalidArgument} if the id is empty or taken, or check_entry refuses it.
  void add(Info info) {
    check_entry(info, infos_);
    check_registry_id(registry_id(info), find(registry_id(info)) != nullptr);
    infos_.push_back(std::move(info));
  }
  const std::vector<Info>& list() const { return infos_; }
  /// @returns the entry called `id`, or nullptr.
  const Info* find(const std::string& id) const {
    for (const Info& info : infos_)
      if (registry_id(info) == id) return &info;
    return nullptr;
  }
  /// A new plugin object from the entry `id`'s factory (for an Info with `create`).
  /// @throws Error{InvalidArgument} naming the known ids if `id` is unknown.
  auto create(const std::string& id) const {
    const Info* info = find(id);
    if (!info) throw Error(ErrorCode::InvalidArgument, "unknown '" + id + "' (known: " + ids() + ")");
    return info->create();
  }
  /// The ids, comma separated ("cut, tear, drill").
  std::string ids() const {
    std::string out;
    for (const Info& info : infos_) out += (out.empty() ? "" : ", ") + registry_id(info);
    return out;
  }

 private:
  std::vector<Info> infos_;
};

}  // namespace deepcut::plugins
