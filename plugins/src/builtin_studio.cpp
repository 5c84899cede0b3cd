// SPDX-License-Identifier: MIT
// The studio's operation tools (tool bar order) and inspectors (menu order): one line per plugin.
#include "deepcut/plugins/inspector_registry.h"
#include "deepcut/plugins/tool.h"
#include "deepcut/plugins/tool_registry.h"

namespace deepcut::plugins {

std::unique_ptr<Tool> create_cut_tool();
std::unique_ptr<Tool> create_tear_tool();
std::unique_ptr<Tool> create_drill_tool();
std::unique_ptr<Tool> create_poke_tool();

void register_weights(InspectorRegistry& registry);
void register_adjacency(InspectorRegistry& registry);
void register_clusters(InspectorRegistry& registry);
void register_pieces(InspectorRegistry& registry);

const ToolRegistry& builtin_tools() {
  static const ToolRegistry registry = [] {
    ToolRegistry r;
    r.add({"cut", "Plane", "P", create_cut_tool});
    r.add({"tear", "Scalpel", "T", create_tear_tool});
    r.add({"drill", "Drill", "D", create_drill_tool});
    r.add({"poke", "Poke", "G", create_poke_tool});  // G as Blender's grab
    return r;
  }();
  return registry;
}

const InspectorRegistry& builtin_inspectors() {
  static const InspectorRegistry registry = [] {
    InspectorRegistry r;
    register_weights(r);
    register_adjacency(r);
    register_clusters(r);
    register_pieces(r);
    return r;
  }();
  return registry;
}

}  // namespace deepcut::plugins
