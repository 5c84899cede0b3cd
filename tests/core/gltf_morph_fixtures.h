// SPDX-License-Identifier: MIT
#pragma once
// Morph-target test inputs built in code: a tiny .glb (`Tiny`) that each test can spoil before
// packing it, and the import-note helpers the morph tests share.

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "deepcut/core/model.h"

namespace deepcut::morph_test {

using nlohmann::json;

inline bool has_note(const Model& model, const std::string& part) {
  for (const auto& n : model.import_notes)
    if (n.find(part) != std::string::npos) return true;
  return false;
}

inline std::string notes_of(const Model& model) {
  std::string out;
  for (const auto& n : model.import_notes) out += n + "\n";
  return out;
}

// A tiny .glb built in the test: a unit quad (two triangles) with normals, two morph targets,
// mesh weights, target names, node weights and a weight channel; `Tiny` lets each test spoil one
// part before `glb()` packs it.
struct Tiny {
  json doc;
  std::vector<unsigned char> bin;

  int view(const void* data, std::size_t bytes) {
    while (bin.size() % 4) bin.push_back(0);
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}});
    const auto* p = static_cast<const unsigned char*>(data);
    bin.insert(bin.end(), p, p + bytes);
    return static_cast<int>(doc["bufferViews"].size() - 1);
  }
  int accessor(json acc) {
    doc["accessors"].push_back(std::move(acc));
    return static_cast<int>(doc["accessors"].size() - 1);
  }
  int floats(const std::vector<float>& v, const char* type, int comps) {
    json acc = {{"bufferView", view(v.data(), v.size() * 4)}, {"componentType", 5126}, {"count", v.size() / std::size_t(comps)},
                {"type", type}};
    if (std::string(type) == "VEC3" || std::string(type) == "SCALAR") {
      std::vector<float> lo(v.begin(), v.begin() + comps), hi = lo;
      for (std::size_t i = 0; i < v.size(); ++i) {
        lo[i % std::size_t(comps)] = std::min(lo[i % std::size_t(comps)], v[i]);
        hi[i % std::size_t(comps)] = std::max(hi[i % std::size_t(comps)], v[i]);
      }
      acc["min"] = lo;
      acc["max"] = hi;
    }
    return accessor(acc);
  }
  // A VEC3 accessor of `count` zeros (no bufferView) overridden at `at` by `values`.
  int sparse_vec3(std::size_t count, const std::vector<std::uint16_t>& at, const std::vector<float>& values) {
    const int iv = view(at.data(), at.size() * 2), vv = view(values.data(), values.size() * 4);
    return accessor({{"componentType", 5126}, {"count", count}, {"type", "VEC3"},
                     {"sparse", {{"count", at.size()}, {"indices", {{"bufferView", iv}, {"componentType", 5123}}}, {"values", {{"bufferView", vv}}}}}});
  }
  std::vector<unsigned char> glb() const {
    json d = doc;
    d["buffers"] = json::array({json{{"byteLength", bin.size()}}});
    std::string text = d.dump();
    while (text.size() % 4) text += ' ';
    std::vector<unsigned char> b = bin;
    while (b.size() % 4) b.push_back(0);
    std::vector<unsigned char> out;
    auto put32 = [&](std::uint32_t v) {
      for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
    };
    put32(0x46546C67u);
    put32(2);
    put32(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + b.size()));
    put32(static_cast<std::uint32_t>(text.size()));
    put32(0x4E4F534Au);
    out.insert(out.end(), text.begin(), text.end());
    put32(static_cast<std::uint32_t>(b.size()));
    put32(0x004E4942u);
    out.insert(out.end(), b.begin(), b.end());
    return out;
  }
};

// The quad: target 0 lifts vertex 2 (sparse, no bufferView), target 1 tilts vertices 1 and 2
// (sparse over a dense base) and turns their normals. The weight channel is a cubic spline.
inline Tiny tiny_quad() {
  Tiny t;
  t.doc["asset"] = {{"version", "2.0"}};
  t.doc["scene"] = 0;
  t.doc["scenes"] = json::array({json{{"nodes", {0, 1}}}});
  t.doc["nodes"] = json::array({json{{"mesh", 0}, {"name", "quad"}, {"weights", {1.0, 0.0}}}, json{{"name", "empty"}}});
  const int pos = t.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3", 3);
  const int nrm = t.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
  const std::vector<std::uint16_t> idx = {0, 1, 2, 0, 2, 3};
  const int ind = t.accessor({{"bufferView", t.view(idx.data(), 12)}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}});
  const int lift = t.sparse_vec3(4, {2}, {0, 0, 0.5f});
  json tilt = t.doc["accessors"][std::size_t(t.floats({0, 0, 0, 0, 0, 0.25f, 0, 0, 0, 0, 0, 0}, "VEC3", 3))];
  const std::vector<std::uint16_t> tilt_at = {2};
  const std::vector<float> tilt_value = {0, 0, 0.25f};
  tilt["sparse"] = {{"count", 1}, {"indices", {{"bufferView", t.view(tilt_at.data(), 2)}, {"componentType", 5123}}},
                    {"values", {{"bufferView", t.view(tilt_value.data(), 12)}}}};
  tilt.erase("min");
  tilt.erase("max");
  const int tilt_acc = t.accessor(tilt);
  const int turn = t.floats({0, 0, 0, -0.1f, 0, 0, -0.1f, 0, 0, 0, 0, 0}, "VEC3", 3);
  json prim = {{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}}}, {"indices", ind}, {"mode", 4},
               {"targets", json::array({json{{"POSITION", lift}}, json{{"POSITION", tilt_acc}, {"NORMAL", turn}}})}};
  t.doc["meshes"] = json::array({json{{"primitives", json::array({prim})}, {"weights", {0.25, 0.75}},
                                      {"extras", {{"targetNames", {"lift", "tilt"}}, {"author", "test"}}}}});
  const int times = t.floats({0, 1}, "SCALAR", 1);
  // Per key: in-tangents (2), values (2), out-tangents (2).
  const int cubic = t.floats({0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0}, "SCALAR", 1);
  const int step_times = t.floats({0, 0.5f, 1}, "SCALAR", 1);
  const int step = t.floats({0, 0, 1, 0, 0, 1}, "SCALAR", 1);
  t.doc["animations"] = json::array(
      {json{{"name", "cubic"},
            {"samplers", json::array({json{{"input", times}, {"output", cubic}, {"interpolation", "CUBICSPLINE"}}})},
            {"channels", json::array({json{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}})}},
       json{{"name", "step"},
            {"samplers", json::array({json{{"input", step_times}, {"output", step}, {"interpolation", "STEP"}}})},
            {"channels", json::array({json{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}})}}});
  return t;
}

// A non-indexed quad whose vertex 3 sits on vertex 0 but morphs elsewhere, and whose vertex 4
// sits on vertex 2 and morphs the same.
inline Tiny coincident_quad() {
  Tiny t;
  t.doc["asset"] = {{"version", "2.0"}};
  t.doc["nodes"] = json::array({json{{"mesh", 0}}});
  const int pos = t.floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3", 3);
  const int d = t.floats({0, 0, 1, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 2, 0, 0, 0}, "VEC3", 3);
  json prim = {{"attributes", {{"POSITION", pos}}}, {"targets", json::array({json{{"POSITION", d}}})}};
  t.doc["meshes"] = json::array({json{{"primitives", json::array({prim})}}});
  return t;
}

// Adds a weight channel on `node` to the first animation: a LINEAR sampler of `times` and `values`.
inline void add_weights_channel(Tiny& t, const std::vector<float>& times, const std::vector<float>& values, int node) {
  json& anim = t.doc["animations"][0];
  anim["samplers"].push_back({{"input", t.floats(times, "SCALAR", 1)}, {"output", t.floats(values, "SCALAR", 1)}});
  anim["channels"].push_back({{"sampler", anim["samplers"].size() - 1}, {"target", {{"node", node}, {"path", "weights"}}}});
}

}  // namespace deepcut::morph_test
