// SPDX-License-Identifier: MIT
// glTF import: morph targets. Each primitive's targets become attributes of its mesh before the
// weld (POSITION deltas per vertex, so coincident vertices that morph apart stay apart; NORMAL and
// TANGENT deltas per corner, like the normals); `mesh.weights`, `extras.targetNames`,
// `node.weights` and the animation channels on `weights` are checked against the target counts.
// Whatever does not fit is dropped or resized and noted, so the model always describes targets
// a writer can export as valid glTF.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "deepcut/core/parallel.h"
#include "io/gltf_reader.h"
#include "uninit_vector.h"

namespace deepcut::gltf_detail {
namespace {

using nlohmann::json;

// What one target costs besides its data (the attribute arrays' bookkeeping, the weld's work per
// vertex): charged against the decoding limit, so a small file cannot list millions of targets.
constexpr std::size_t kTargetOverheadBytes = 4096;

std::string node_label(const Model& model, int node) {
  const std::string& name = model.nodes[std::size_t(node)].name;
  return "node " + std::to_string(node) + (name.empty() ? "" : " '" + name + "'");
}

// Keeps the samplers some channel uses, renumbered in order.
void drop_unused_samplers(Animation& anim) {
  std::vector<int> renumber(anim.samplers.size(), -1);
  std::vector<AnimationSampler> kept;
  for (auto& ch : anim.channels) {
    int& to = renumber[std::size_t(ch.sampler)];
    if (to < 0) {
      to = static_cast<int>(kept.size());
      kept.push_back(std::move(anim.samplers[std::size_t(ch.sampler)]));
    }
    ch.sampler = to;
  }
  anim.samplers = std::move(kept);
}

}  // namespace

void MorphArrays::add(ArrayBuild& build, std::size_t nv, const Uints& tris,
                      const std::vector<MorphTarget>& targets) {
  const std::size_t nc = tris.size();
  // The per-corner ones with room (operation_corner_room).
  const std::uint32_t* t = tris.data();
  auto add = [&](bool per_corner, std::string name, const Floats& deltas) {
    built_.push_back({per_corner, std::move(name), std::make_unique<AttributeArray<glm::vec3>>()});
    const float* d = deltas.data();
    if (per_corner)
      build.add(&built_.back().array->data(), nc, operation_corner_room(nc / 3), [d, t](std::size_t c) {
        return glm::vec3(d[3 * std::size_t(t[c])], d[3 * std::size_t(t[c]) + 1], d[3 * std::size_t(t[c]) + 2]);
      });
    else  // -0 reads as +0, as positions do, so the weld sees equal deltas
      build.add(&built_.back().array->data(), nv, nv, [d](std::size_t v) {
        return glm::vec3(d[3 * v] + 0.0f, d[3 * v + 1] + 0.0f, d[3 * v + 2] + 0.0f);
      });
  };
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const int n = static_cast<int>(i);
    add(false, attr::morph_position_name(n), targets[i].position);
    if (!targets[i].normal.empty()) add(true, attr::morph_normal_name(n), targets[i].normal);
    if (!targets[i].tangent.empty()) add(true, attr::morph_tangent_name(n), targets[i].tangent);
  }
}

void MorphArrays::put_into(SurfaceMesh& mesh) {
  for (Built& b : built_)
    (b.per_corner ? mesh.corner_attrs() : mesh.vertex_attrs()).put(b.name, std::move(b.array));
  built_.clear();
}

void Reader::charge_decode(std::size_t bytes, const std::string& what) {
  if (bytes > decode_left_)
    fail(what + ": its arrays would take the model past the decoding limit; the file claims far more data than it holds");
  decode_left_ -= bytes;
}

// glTF wants every primitive of a mesh to have as many targets; a file that breaks this keeps the
// targets all its primitives have (the first ones: targets are matched by position in the list).
std::size_t Reader::mesh_target_count(std::size_t m, const std::string& where) {
  const auto& prims = gltf_.meshes[m].primitives;
  if (prims.empty()) return 0;
  std::size_t lo = std::numeric_limits<std::size_t>::max(), hi = 0;
  for (const auto& p : prims) {
    lo = std::min(lo, p.targets.size());
    hi = std::max(hi, p.targets.size());
  }
  if (lo != hi)
    problem("morph-targets-dropped", hi - lo,
            {"morph target past the count every primitive of its mesh has dropped",
             "morph targets past the count every primitive of their mesh has dropped"},
            where + " (" + std::to_string(lo) + " kept)");
  return lo;
}

std::vector<MorphTarget> Reader::read_targets(const tinygltf::Primitive& p, const std::string& where, std::size_t nv,
                                              std::size_t corners, std::size_t count) {
  std::vector<MorphTarget> out(count);
  const bool has_normal = p.attributes.count("NORMAL") != 0, has_tangent = p.attributes.count("TANGENT") != 0;
  std::size_t without_base = 0, other = 0;
  for (std::size_t t = 0; t < count; ++t) {
    const std::string target = "morph target " + std::to_string(t);
    charge_decode(kTargetOverheadBytes + nv * sizeof(glm::vec3), where + ": " + target);
    for (const auto& [name, accessor] : p.targets[t]) {
      Floats* into = name == "POSITION" ? &out[t].position
                                 : name == "NORMAL"  ? &out[t].normal
                                 : name == "TANGENT" ? &out[t].tangent
                                                     : nullptr;
      if (!into) {
        ++other;
        continue;
      }
      if ((name == "NORMAL" && !has_normal) || (name == "TANGENT" && !has_tangent)) {
        ++without_base;  // glTF forbids a delta of an attribute the primitive lacks
        continue;
      }
      const std::string what = target + " " + name;
      int comps = 0;
      *into = read_floats(accessor, what.c_str(), &comps);
      if (comps != 3) fail(where + ": " + what + " is not VEC3");
      if (into->size() != 3 * nv)
        fail(where + ": " + what + " has " + std::to_string(into->size() / 3) + " elements, POSITION has " + std::to_string(nv));
      const Floats& deltas = *into;
      const std::size_t bad = first_bad(deltas.size(), [&](std::size_t i) { return !std::isfinite(deltas[i]); });
      if (bad < deltas.size()) fail(where + ": " + what + " delta " + std::to_string(bad / 3) + " is not finite (NaN or Inf)");
      if (name != "POSITION") charge_decode(corners * sizeof(glm::vec3), where + ": " + what);
    }
    if (out[t].position.empty()) out[t].position.assign(3 * nv, 0.0f);
  }
  if (without_base)
    problem("morph-deltas-dropped", without_base,
            {"morph NORMAL/TANGENT delta dropped (the primitive has no such attribute to morph)",
             "morph NORMAL/TANGENT deltas dropped (the primitive has no such attribute to morph)"},
            where);
  if (other)
    problem("morph-attributes-dropped", other,
            {"morph target attribute other than POSITION, NORMAL, TANGENT dropped",
             "morph target attributes other than POSITION, NORMAL, TANGENT dropped"},
            where);
  return out;
}

// `mesh.weights` sized to the target count (zeros when absent), and `extras.targetNames` when it
// names each target; names of targets dropped above are dropped with them.
void Reader::read_mesh_weights(Mesh& mesh, std::size_t m, const std::string& where, std::size_t count) {
  const auto& g = gltf_.meshes[m];
  for (const double w : g.weights)
    if (!std::isfinite(static_cast<float>(w))) fail(where + ": a morph weight is not finite (a value overflows a 32-bit float)");
  if (!g.weights.empty() && g.weights.size() != count)
    problem("mesh-weights-resized", 1,
            {"mesh's morph weights fitted to its target count (extra ones dropped, missing ones 0)",
             "meshes' morph weights fitted to their target count (extra ones dropped, missing ones 0)"},
            where + " (" + std::to_string(g.weights.size()) + " for " + std::to_string(count) + ")");
  mesh.weights.assign(count, 0.0f);
  for (std::size_t t = 0; t < count && t < g.weights.size(); ++t) mesh.weights[t] = static_cast<float>(g.weights[t]);

  if (mesh.extras_json.empty()) return;
  json extras = json::parse(mesh.extras_json, nullptr, /*allow_exceptions=*/false);
  if (!extras.is_object() || !extras.contains("targetNames") || !extras["targetNames"].is_array()) return;
  json& names = extras["targetNames"];
  std::size_t declared = 0;
  for (const auto& p : g.primitives) declared = std::max(declared, p.targets.size());
  if (names.size() > count && names.size() == declared) {
    names.erase(names.begin() + static_cast<std::ptrdiff_t>(count), names.end());
    if (count == 0) extras.erase("targetNames");
    mesh.extras_json = extras.dump();
    problem("target-names-cut", 1,
            {"mesh's extras.targetNames cut to the targets kept", "meshes' extras.targetNames cut to the targets kept"},
            where);
  }
  if (!extras.contains("targetNames") || names.size() != count) {
    if (extras.contains("targetNames"))
      problem("target-names-unused", 1,
              {"mesh's extras.targetNames does not name each target (kept, not used as names)",
               "meshes' extras.targetNames do not name each target (kept, not used as names)"},
              where + " (" + std::to_string(names.size()) + " names, " + std::to_string(count) + " targets)");
    return;
  }
  std::vector<std::string> out;
  for (const auto& n : names) {
    if (!n.is_string()) return;
    out.push_back(n.get<std::string>());
  }
  mesh.target_names = std::move(out);
}

// A sampler of a channel on `weights` holds SCALAR outputs, one per morph target per key (three
// per key for a cubic spline): sets `s.components` to that target count, or notes why the channel
// is dropped. The count is checked against the node's mesh by resolve_morph_weights.
bool Reader::fit_weights_sampler(AnimationSampler& s, int output_type, std::size_t animation, std::size_t channel) {
  const std::string where = "animation " + std::to_string(animation) + " channel " + std::to_string(channel);
  if (output_type != TINYGLTF_TYPE_SCALAR) {
    problem("morph-channels-not-scalar", 1,
            {"morph weight channel dropped (its outputs are not SCALAR)",
             "morph weight channels dropped (their outputs are not SCALAR)"},
            where);
    return false;
  }
  const std::size_t keys = s.input.size() * (s.interpolation == Interpolation::CubicSpline ? 3 : 1);
  if (keys == 0 || s.output.size() % keys != 0) {
    problem("morph-channels-bad-count", 1,
            {"morph weight channel dropped (not a whole number of weights per key)",
             "morph weight channels dropped (not a whole number of weights per key)"},
            where + " (" + std::to_string(s.output.size()) + " weights, " + std::to_string(s.input.size()) + " keys)");
    return false;
  }
  s.components = static_cast<int>(s.output.size() / keys);
  return true;
}

// Runs once the meshes are read: `node.weights` must have one weight per target of the node's
// mesh, and a weight channel must drive a node whose mesh has targets, with one value per target
// per key, and no other channel on that node's weights.
void Reader::resolve_morph_weights() {
  auto targets_of = [&](int node) -> std::size_t {
    const int mesh = model_.nodes[std::size_t(node)].mesh;
    return mesh >= 0 && static_cast<std::size_t>(mesh) < model_.meshes.size() ? model_.meshes[std::size_t(mesh)].target_count() : 0;
  };
  for (std::size_t i = 0; i < model_.nodes.size(); ++i) {
    Node& n = model_.nodes[i];
    const std::size_t count = targets_of(static_cast<int>(i));
    if (n.weights.empty() || n.weights.size() == count) continue;
    problem("node-weights-resized", 1,
            {"node's morph weights fitted to its mesh's target count (extra ones dropped, missing ones 0)",
             "nodes' morph weights fitted to their mesh's target count (extra ones dropped, missing ones 0)"},
            node_label(model_, static_cast<int>(i)) + " (" + std::to_string(n.weights.size()) + " for " +
                std::to_string(count) + ")");
    n.weights.resize(count, 0.0f);
  }
  for (std::size_t a = 0; a < model_.animations.size(); ++a) {
    Animation& anim = model_.animations[a];
    std::vector<AnimationChannel> kept;
    std::vector<int> driven;  // nodes whose weights a kept channel drives
    for (const auto& ch : anim.channels) {
      if (ch.path != AnimationPath::Weights) {
        kept.push_back(ch);
        continue;
      }
      const std::size_t count = targets_of(ch.node);
      const AnimationSampler& s = anim.samplers[std::size_t(ch.sampler)];
      std::string why;
      if (count == 0) why = "its mesh has no morph targets";
      else if (static_cast<std::size_t>(s.components) != count)
        why = std::to_string(s.components) + " weights per key for " + std::to_string(count) + " morph targets";
      else if (std::find(driven.begin(), driven.end(), ch.node) != driven.end()) why = "another channel drives the same weights";
      if (why.empty()) {
        kept.push_back(ch);
        driven.push_back(ch.node);
      } else {
        problem("morph-channels-dropped", 1,
                {"morph weight channel dropped (it does not fit its node's mesh)",
                 "morph weight channels dropped (they do not fit their nodes' meshes)"},
                "animation " + std::to_string(a) + (anim.name.empty() ? "" : " '" + anim.name + "'") + " " +
                    node_label(model_, ch.node) + " (" + why + ")");
      }
    }
    anim.channels = std::move(kept);
    drop_unused_samplers(anim);  // also those of weight channels refused while reading
  }
}

}  // namespace deepcut::gltf_detail
