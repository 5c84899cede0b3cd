// SPDX-License-Identifier: MIT
#include "deepcut/core/ops/operation.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <nlohmann/json.hpp>

namespace deepcut {
namespace {

using nlohmann::json;

[[noreturn]] void fail(std::size_t index, const std::string& what) {
  throw Error(ErrorCode::InvalidInput, "history operation " + std::to_string(index) + ": " + what);
}

std::vector<float> numbers(const json& o, const char* key, std::size_t count, std::size_t index, bool scalar = false) {
  if (scalar) {
    if (!o.contains(key) || !o[key].is_number() || !std::isfinite(o[key].get<double>()))
      fail(index, std::string("'") + key + "' must be a number");
    return {o[key].get<float>()};
  }
  if (!o.contains(key) || !o[key].is_array() || o[key].size() != count)
    fail(index, std::string("'") + key + "' must be a list of " + std::to_string(count) + " numbers");
  std::vector<float> out;
  for (const auto& v : o[key]) {
    if (!v.is_number() || !std::isfinite(v.get<double>())) fail(index, std::string("'") + key + "' holds a non-number");
    out.push_back(v.get<float>());
  }
  return out;
}

const char* keep_name(CutKeep k) { return k == CutKeep::Both ? "both" : k == CutKeep::Positive ? "positive" : "negative"; }

json to_json(const Operation& op) {
  json out;
  std::visit(
      [&](const auto& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, CutOperation>) {
          out = {{"op", "cut"},
                 {"plane", {p.plane.point.x, p.plane.point.y, p.plane.point.z, p.plane.normal.x, p.plane.normal.y, p.plane.normal.z}},
                 {"keep", keep_name(p.options.keep)},
                 {"cap", p.options.cap},
                 {"components", p.options.split_components}};
        } else if constexpr (std::is_same_v<T, TearOperation>) {
          out = {{"op", "tear"},
                 {"blade_start", {p.start.handle.x, p.start.handle.y, p.start.handle.z, p.start.tip.x, p.start.tip.y, p.start.tip.z}},
                 {"blade_end", {p.end.handle.x, p.end.handle.y, p.end.handle.z, p.end.tip.x, p.end.tip.y, p.end.tip.z}}};
          if (p.options.width >= 0.0f) out["width"] = p.options.width;
        } else if constexpr (std::is_same_v<T, DrillOperation>) {
          const Cylinder& c = p.cylinder;
          out = {{"op", "drill"},
                 {"axis", {c.a.x, c.a.y, c.a.z, c.b.x, c.b.y, c.b.z}},
                 {"radius", c.radius},
                 {"min_rim_edges", p.options.min_rim_edges},
                 {"wall", p.options.wall}};
        }
      },
      op.params);
  out["time"] = op.time;
  out["animation"] = op.animation;
  if (!op.weights.empty()) {
    json weights = json::object();
    for (const auto& [node, w] : op.weights) weights[std::to_string(node)] = w;
    out["weights"] = weights;
  }
  return out;
}

// "weights": {"NODE": [w0, w1, ...], ...}, the morph weights set by hand per node.
std::map<int, std::vector<float>> parse_weights(const json& o, std::size_t index) {
  std::map<int, std::vector<float>> out;
  if (!o.contains("weights")) return out;
  const json& w = o["weights"];
  const char* shape = "'weights' must map node indices to lists of numbers";
  if (!w.is_object()) fail(index, shape);
  for (const auto& item : w.items()) {
    const std::string& key = item.key();
    if (key.empty() || key.size() > 9 || !std::all_of(key.begin(), key.end(), [](char c) { return c >= '0' && c <= '9'; }))
      fail(index, shape);
    if (!item.value().is_array()) fail(index, shape);
    std::vector<float>& weights = out[std::stoi(key)];
    for (const auto& v : item.value()) {
      if (!v.is_number() || !std::isfinite(v.get<double>())) fail(index, "'weights' holds a non-number");
      weights.push_back(v.get<float>());
    }
  }
  return out;
}

// A boolean member, false when absent. @throws (via fail) when present with another type.
bool flag(const json& o, const char* key, std::size_t index) {
  if (!o.contains(key)) return false;
  if (!o[key].is_boolean()) fail(index, std::string("'") + key + "' must be true or false");
  return o[key].get<bool>();
}

// Members an operation of kind `kind` may have; anything else is a typo the user should hear of.
void reject_unknown_keys(const json& o, const std::string& kind, std::size_t index) {
  std::vector<std::string> allowed = {"op", "time", "animation", "weights"};
  if (kind == "cut") allowed.insert(allowed.end(), {"plane", "keep", "cap", "components"});
  if (kind == "tear") allowed.insert(allowed.end(), {"blade_start", "blade_end", "width"});
  if (kind == "drill") allowed.insert(allowed.end(), {"axis", "radius", "min_rim_edges", "wall"});
  for (const auto& item : o.items())
    if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end())
      fail(index, "unknown key '" + item.key() + "' for a " + kind + " operation");
}

Operation from_json(const json& o, std::size_t index) {
  if (!o.is_object()) fail(index, "is not an object");
  if (!o.contains("op") || !o["op"].is_string()) fail(index, "'op' must be \"cut\", \"tear\" or \"drill\"");
  const std::string kind = o["op"].get<std::string>();
  if (kind != "cut" && kind != "tear" && kind != "drill") fail(index, "unknown op '" + kind + "'");
  reject_unknown_keys(o, kind, index);
  Operation op;
  op.animation = 0;  // absent: the model's first animation (the rest pose when it has none)
  if (o.contains("time")) {
    if (!o["time"].is_number() || !std::isfinite(o["time"].get<double>())) fail(index, "'time' must be a number");
    op.time = o["time"].get<float>();
  }
  if (o.contains("animation")) {
    if (!o["animation"].is_number_integer() || o["animation"].get<int>() < -1)
      fail(index, "'animation' must be an animation index, or -1 for the rest pose");
    op.animation = o["animation"].get<int>();
  }
  op.weights = parse_weights(o, index);
  if (kind == "cut") {
    CutOperation c;
    const auto p = numbers(o, "plane", 6, index);
    c.plane = {{p[0], p[1], p[2]}, {p[3], p[4], p[5]}};
    if (o.contains("keep") && !o["keep"].is_string()) fail(index, "'keep' must be both, positive or negative");
    const std::string keep = o.value("keep", "both");
    if (keep == "both") c.options.keep = CutKeep::Both;
    else if (keep == "positive") c.options.keep = CutKeep::Positive;
    else if (keep == "negative") c.options.keep = CutKeep::Negative;
    else fail(index, "'keep' must be both, positive or negative");
    c.options.cap = flag(o, "cap", index);
    c.options.split_components = flag(o, "components", index);
    op.params = c;
  } else if (kind == "tear") {
    TearOperation t;
    const auto s = numbers(o, "blade_start", 6, index);
    const auto e = numbers(o, "blade_end", 6, index);
    t.start = {{s[0], s[1], s[2]}, {s[3], s[4], s[5]}};
    t.end = {{e[0], e[1], e[2]}, {e[3], e[4], e[5]}};
    if (o.contains("width")) {
      if (!o["width"].is_number() || !std::isfinite(o["width"].get<double>()) || o["width"].get<double>() < 0.0)
        fail(index, "'width' must be a number >= 0");
      t.options.width = o["width"].get<float>();
    }
    op.params = t;
  } else if (kind == "drill") {
    DrillOperation d;
    const auto a = numbers(o, "axis", 6, index);
    d.cylinder.a = {a[0], a[1], a[2]};
    d.cylinder.b = {a[3], a[4], a[5]};
    d.cylinder.radius = numbers(o, "radius", 1, index, true)[0];
    if (o.contains("min_rim_edges")) {
      if (!o["min_rim_edges"].is_number_integer()) fail(index, "'min_rim_edges' must be an integer");
      d.options.min_rim_edges = o["min_rim_edges"].get<int>();
    }
    d.options.wall = flag(o, "wall", index);
    op.params = d;
  } else {
    fail(index, "unknown op '" + kind + "'");
  }
  return op;
}

}  // namespace

History parse_history(const std::string& json_text) {
  const json doc = json::parse(json_text, nullptr, false);
  if (doc.is_discarded()) throw Error(ErrorCode::InvalidInput, "history: invalid JSON");
  if (!doc.is_object() || !doc.contains("operations") || !doc["operations"].is_array())
    throw Error(ErrorCode::InvalidInput, "history: expected an object with an \"operations\" list");
  History h;
  for (std::size_t i = 0; i < doc["operations"].size(); ++i) h.operations.push_back(from_json(doc["operations"][i], i));
  return h;
}

std::string history_to_json(const History& history) {
  json ops = json::array();
  for (const auto& op : history.operations) ops.push_back(to_json(op));
  return json{{"operations", ops}}.dump();
}

const char* operation_name(const Operation& operation) {
  if (std::holds_alternative<CutOperation>(operation.params)) return "cut";
  if (std::holds_alternative<TearOperation>(operation.params)) return "tear";
  return "drill";
}

void check_operation(const Operation& operation, const ParameterName& name) {
  if (const auto* cut = std::get_if<CutOperation>(&operation.params)) {
    check_cut_plane(cut->plane);
  } else if (const auto* tear = std::get_if<TearOperation>(&operation.params)) {
    swept_quad_triangles(tear->start, tear->end);  // throws for a degenerate blade or sweep
  } else if (const auto* drill = std::get_if<DrillOperation>(&operation.params)) {
    check_drill_arguments(drill->cylinder, drill->options, name);
  }
}

namespace {

// Live triangles drawn by each node (0 for nodes without a mesh).
std::vector<std::size_t> instance_triangles(const Model& model) {
  std::vector<std::size_t> out(model.nodes.size(), 0);
  for (std::size_t ni = 0; ni < model.nodes.size(); ++ni) {
    const int mi = model.nodes[ni].mesh;
    if (mi < 0 || static_cast<std::size_t>(mi) >= model.meshes.size()) continue;
    for (const auto& prim : model.meshes[static_cast<std::size_t>(mi)].primitives) out[ni] += prim.mesh.face_count();
  }
  return out;
}

// drill_model, refusing a drill that swallows a whole instance when the options say so: such a
// drill is not a hole, and the node would be left without a mesh.
ModelDrillResult drill_instances(Model& model, const DrillOperation& drill, int animation, float time,
                                 PosedModel& posed) {
  if (!drill.options.refuse_swallowed_instances)
    return drill_model(model, posed, drill.cylinder, drill.options, animation, time);
  const auto before = instance_triangles(model);
  ModelDrillResult result = drill_model(model, posed, drill.cylinder, drill.options, animation, time);
  const auto after = instance_triangles(model);
  for (std::size_t ni = 0; ni < before.size(); ++ni)
    if (before[ni] > 0 && after[ni] == 0)
      throw Error(ErrorCode::InvalidArgument,
                  "the cylinder removes every triangle of node " + std::to_string(ni) +
                      (model.nodes[ni].name.empty() ? std::string() : " '" + model.nodes[ni].name + "'") + " (" +
                      std::to_string(before[ni]) + " triangles); use a smaller radius");
  return result;
}

}  // namespace

OperationResult apply_operation(Model& model, const Operation& operation) {
  PosedModel posed;
  return apply_operation(model, operation, posed);
}

OperationResult apply_operation(Model& model, const Operation& operation, PosedModel& posed) {
  OperationResult out;
  const int animation = operation.animation >= 0 && model.animations.empty() ? -1 : operation.animation;
  // The pose includes the morph weights set by hand: the operations' own `prepare` keeps them.
  const PoseKey key(animation, operation.time, operation.weights);
  if (posed.key().weights != operation.weights) posed.prepare(model, key, PoseDetail::Positions);
  std::visit(
      [&](const auto& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, CutOperation>) {
          // A warm posed model at the operation's pose (the studio's, `deepcut apply`'s) is used as
          // it is: the cut reads its positions and poses nothing again. One at another pose is left
          // as it was, and the cut poses the model on its own (positions only).
          PosedModel own;
          PosedModel& cut_posed = posed.matches(key) ? posed : own;
          if (&cut_posed == &own && !operation.weights.empty()) own.prepare(model, key, PoseDetail::Positions);
          const ModelCutResult r = cut_model(model, cut_posed, p.plane, p.options, animation, operation.time);
          // The cut replaces meshes and adds nodes: the next operation poses the model anew.
          if (r.status == OpStatus::Ok) posed.invalidate();
          out.status = r.status;
          out.result = r;
        } else if constexpr (std::is_same_v<T, TearOperation>) {
          const ModelTearResult r = tear_model(model, posed, p.start, p.end, p.options, animation, operation.time);
          out.status = r.status;
          out.result = r;
        } else if constexpr (std::is_same_v<T, DrillOperation>) {
          const ModelDrillResult r = drill_instances(model, p, animation, operation.time, posed);
          out.status = r.status;
          out.result = r;
        }
      },
      operation.params);
  if (out.status == OpStatus::Ok) record_operation(model, operation);
  return out;
}

History model_history(const Model& model) {
  if (model.extras_json.empty()) return {};
  const json extras = json::parse(model.extras_json, nullptr, false);
  if (!extras.is_object() || !extras.contains("deepcut_history")) return {};
  return parse_history(extras["deepcut_history"].dump());
}

void record_operation(Model& model, const Operation& operation) {
  json extras = model.extras_json.empty() ? json::object() : json::parse(model.extras_json, nullptr, false);
  if (!extras.is_object()) extras = json::object();
  if (!extras.contains("deepcut_history") || !extras["deepcut_history"].is_object())
    extras["deepcut_history"] = {{"operations", json::array()}};
  extras["deepcut_history"]["operations"].push_back(to_json(operation));
  model.extras_json = extras.dump();
}

}  // namespace deepcut
