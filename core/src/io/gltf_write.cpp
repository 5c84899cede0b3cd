// SPDX-License-Identifier: MIT
// glTF export: un-welds corners into glTF vertices, packs one binary buffer, writes the JSON with
// nlohmann (so carried-through objects are emitted verbatim) and replaces the target atomically.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

#include <nlohmann/json.hpp>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/parallel.h"
#include "byte_rows.h"
#include "first_of_class.h"
#include "io/gltf_common.h"
#include "io/gltf_write_compress.h"

namespace deepcut {
namespace {

using nlohmann::json;
using namespace gltf_detail;

constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

// A normal, tangent or rotation this close to unit length is written as it is: dividing it by its length
// again would move its last bit, so exporting an imported export would not give the same bytes.
// (The validator accepts lengths within 5e-4 of 1; a division lands within 1e-7.)
bool unit_enough(float length) { return std::abs(length - 1.0f) <= 1e-6f; }

constexpr std::size_t kGrain = 16384;

// Calls fn(i) for every i in [0, n) in parallel chunks; each call writes only element i's output.
template <class Fn>
void each(std::size_t n, Fn&& fn) {
  parallel_for(n, kGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) fn(i);
  });
}

json parse_or(const std::string& text, json fallback) {
  if (text.empty()) return fallback;
  return json::parse(text, nullptr, /*allow_exceptions=*/false);
}

// The glTF vertices of a mesh: one per distinct (vertex, exported corner attributes), numbered
// in order of first use by the corners.
using detail::Indices;

struct GltfVertices {
  Indices vertex;                      // glTF vertex -> mesh vertex
  Indices corner;                      // glTF vertex -> a corner it came from
  Indices indices;                     // corner -> glTF vertex
};

// A .glb up to its binary chunk's bytes: the header, the JSON chunk of `doc` and, when `bin_size`
// bytes follow, the binary chunk's header.
std::vector<unsigned char> glb_start(const json& doc, std::size_t bin_size) {
  std::string text = doc.dump();
  while (text.size() % 4) text += ' ';
  const std::uint32_t total =
      static_cast<std::uint32_t>(12 + 8 + text.size() + (bin_size == 0 ? 0 : 8 + bin_size));
  std::vector<unsigned char> out;
  out.reserve(total - bin_size);
  auto put32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
  };
  put32(0x46546C67u);  // "glTF"
  put32(2);
  put32(total);
  put32(static_cast<std::uint32_t>(text.size()));
  put32(0x4E4F534Au);  // "JSON"
  out.insert(out.end(), text.begin(), text.end());
  if (bin_size != 0) {
    put32(static_cast<std::uint32_t>(bin_size));
    put32(0x004E4942u);  // "BIN\0"
  }
  return out;
}

class Writer {
 public:
  Writer(const Model& model, const ExportOptions& options) : model_(model), options_(options) {}
  // The file: for a .glb its header, JSON and BIN chunk header, then `bin()`; for a .gltf the
  // whole text (`bin()` is then not part of the file).
  std::vector<unsigned char> write(bool glb);
  const detail::UninitVector<unsigned char>& bin() const { return bin_; }

 private:
  int add_view(std::size_t bytes, int target, std::size_t* at);
  // An accessor of `count` elements of `components` T's over a new view, the view's bytes not yet
  // written: the caller fills `data<T>(*at)` (straight into the binary buffer, no copy).
  template <class T>
  int add_accessor(std::size_t count, int components, int component_type, const char* type, int target, std::size_t* at);
  template <class T, class A>
  int add_accessor(const std::vector<T, A>& data, int components, int component_type, const char* type, int target,
                   bool minmax = false);
  template <class T>
  T* data(std::size_t at) {
    return reinterpret_cast<T*>(bin_.data() + at);
  }
  // Gives the accessor the per-component min / max glTF wants (of its data, once written).
  template <class T>
  void add_min_max(int accessor, std::size_t at, std::size_t count, int components);
  void write_meshes();
  void write_primitive(const Primitive& prim, std::size_t targets, json& out);
  json write_targets(const SurfaceMesh& mesh, const GltfVertices& vertices, std::size_t targets,
                     const std::vector<std::string>& morph_corners);
  void write_influences(const SurfaceMesh& mesh, const Indices& out_vertex, json& attributes);
  void write_corner_attribute(const SurfaceMesh& mesh, const std::string& name, const AttributeArrayBase& corner_array,
                              const Indices& out_corner, json& attributes);
  void write_skins();
  void write_animations();
  void write_nodes();
  bool drives_written_targets(int node, int components) const;
  void write_images();
  void write_asset();
  void write_passthrough();
  void write_extensions_and_extras();
  void write_buffer(bool glb);
  void reserve_bin(std::size_t bytes);
  std::size_t tail_bound() const;

  const Model& model_;
  ExportOptions options_;
  json doc_ = json::object();
  detail::UninitVector<unsigned char> bin_;
  std::size_t tail_ = 0;       // tail_bound(), computed once per write
  std::vector<int> mesh_map_;  // model mesh -> glTF mesh (-1 when dropped)
  std::vector<std::size_t> mesh_targets_;  // model mesh -> morph targets written (0 when dropped)
};

int Writer::add_view(std::size_t bytes, int target, std::size_t* at) {
  while (bin_.size() % 4) bin_.push_back(0);
  *at = bin_.size();
  json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}};
  if (target) view["target"] = target;
  bin_.resize(bin_.size() + bytes);
  doc_["bufferViews"].push_back(view);
  return static_cast<int>(doc_["bufferViews"].size() - 1);
}

template <class T>
int Writer::add_accessor(std::size_t count, int components, int component_type, const char* type, int target,
                         std::size_t* at) {
  json acc = {{"bufferView", add_view(count * std::size_t(components) * sizeof(T), target, at)},
              {"componentType", component_type},
              {"count", count},
              {"type", type}};
  doc_["accessors"].push_back(acc);
  return static_cast<int>(doc_["accessors"].size() - 1);
}

template <class T, class A>
int Writer::add_accessor(const std::vector<T, A>& data, int components, int component_type, const char* type, int target,
                         bool minmax) {
  const std::size_t count = data.size() / std::size_t(components);
  std::size_t at = 0;
  const int accessor = add_accessor<T>(count, components, component_type, type, target, &at);
  T* out = reinterpret_cast<T*>(bin_.data() + at);
  parallel_for(data.size(), kGrain, [&](std::size_t b, std::size_t e) { std::memcpy(out + b, data.data() + b, (e - b) * sizeof(T)); });
  if (minmax) add_min_max<T>(accessor, at, count, components);
  return accessor;
}

template <class T>
void Writer::add_min_max(int accessor, std::size_t at, std::size_t count, int components) {
  if (count == 0) return;
  const T* values = data<T>(at);
  using Range = std::pair<std::vector<T>, std::vector<T>>;
  const std::vector<T> first(values, values + components);
  const Range range = parallel_reduce(
      count, kGrain, Range(first, first),
      [&](std::size_t b, std::size_t e) {
        Range r(first, first);
        for (std::size_t i = b; i < e; ++i)
          for (int c = 0; c < components; ++c) {
            r.first[c] = std::min(r.first[c], values[i * components + c]);
            r.second[c] = std::max(r.second[c], values[i * components + c]);
          }
        return r;
      },
      [&](Range sum, const Range& r) {
        for (int c = 0; c < components; ++c) {
          sum.first[c] = std::min(sum.first[c], r.first[c]);
          sum.second[c] = std::max(sum.second[c], r.second[c]);
        }
        return sum;
      });
  json& acc = doc_["accessors"][std::size_t(accessor)];
  acc["min"] = range.first;
  acc["max"] = range.second;
}

// Un-welds `mesh` (no deleted faces) by the corner attributes in `arrays`: a glTF vertex per
// class of corners sharing a vertex and those attributes, numbered by first corner. Only corners
// of one vertex can share a glTF vertex, so each vertex's corners are compared among themselves
// (in parallel over the vertices; the numbering does not depend on the thread count).
GltfVertices unweld(const SurfaceMesh& mesh, const std::vector<const AttributeArrayBase*>& arrays) {
  detail::ByteRows rows;
  for (const auto* a : arrays) rows.add(*a);
  const auto& tris = mesh.faces();
  const std::size_t corners = 3 * tris.size();
  auto vertex_of = [&](std::size_t c) { return tris[c / 3][static_cast<int>(c % 3)].index; };
  const detail::Groups by_vertex = detail::group_by_key(corners, mesh.vertex_count(), vertex_of);
  const auto first = detail::first_of_class_in_groups(
      by_vertex, corners, [&](std::uint32_t c) { return detail::ByteRows::finish(rows.hash(c)); },
      [&](std::uint32_t c0, std::uint32_t c1) { return rows.equal(c0, c1); });
  GltfVertices out;
  out.corner = detail::ordered_indices(corners, [&](std::size_t c) { return first[c] == c; });
  const std::size_t n = out.corner.size();
  out.vertex.resize(n);
  Indices id(corners);  // read only at the first corner of each class, which the loop below sets
  parallel_for(n, detail::kClassGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      out.vertex[k] = vertex_of(out.corner[k]);
      id[out.corner[k]] = static_cast<std::uint32_t>(k);
    }
  });
  out.indices.resize(corners);
  parallel_for(corners, detail::kClassGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) out.indices[c] = id[first[c]];
  });
  return out;
}

// How many morph targets `mesh` carries: the consecutive `attr::morph_position_name(i)` from 0.
std::size_t morph_targets(const SurfaceMesh& mesh) {
  std::size_t n = 0;
  while (mesh.vertex_attrs().find<glm::vec3>(attr::morph_position_name(static_cast<int>(n)))) ++n;
  return n;
}

// The per-corner morph deltas of the first `targets` targets that the written primitive can carry
// (glTF wants the base NORMAL / TANGENT beside a NORMAL / TANGENT delta): they split glTF vertices
// as normals do.
std::vector<std::string> morph_corner_names(const SurfaceMesh& mesh, std::size_t targets) {
  std::vector<std::string> out;
  const auto& ca = mesh.corner_attrs();
  for (std::size_t t = 0; t < targets; ++t) {
    const int i = static_cast<int>(t);
    if (ca.contains(attr::kNormal) && ca.find<glm::vec3>(attr::morph_normal_name(i))) out.push_back(attr::morph_normal_name(i));
    if (ca.contains(attr::kTangent) && ca.find<glm::vec3>(attr::morph_tangent_name(i))) out.push_back(attr::morph_tangent_name(i));
  }
  return out;
}

// glTF attribute name for one of our attribute names ("" if it is not exported).
std::string gltf_name(const std::string& name) {
  if (name == attr::kNormal) return "NORMAL";
  if (name == attr::kTangent) return "TANGENT";
  if (name == attr::kColor0) return "COLOR_0";
  if (name.rfind("c:uv", 0) == 0) return "TEXCOORD_" + name.substr(4);
  return "";
}

// At least the bytes of a primitive of `mesh` (no deleted faces) with `n` glTF vertices: every
// array it writes per glTF vertex (of at most the bytes of all its vertex and corner
// attributes), its indices and the views' alignment.
std::size_t primitive_bound(const SurfaceMesh& mesh, std::size_t n) {
  std::size_t per_vertex = 0, arrays = 2;
  for (const auto* set : {&mesh.vertex_attrs(), &mesh.corner_attrs()})
    for (const auto& name : set->names()) {
      per_vertex += set->base(name)->element_bytes();
      ++arrays;
    }
  return n * per_vertex + 3 * mesh.faces().size() * sizeof(std::uint32_t) + 4 * arrays + 256;
}

void Writer::write_primitive(const Primitive& prim, std::size_t targets, json& out) {
  const SurfaceMesh* src = &prim.mesh;
  SurfaceMesh compacted;
  if (prim.mesh.face_count() != prim.mesh.face_slots()) {
    compacted = prim.mesh;
    compacted.compact();
    src = &compacted;
  }
  const SurfaceMesh& mesh = *src;
  const auto& ca = mesh.corner_attrs();
  std::vector<const AttributeArrayBase*> arrays;
  std::vector<std::string> exported;
  for (const auto& n : ca.names())
    if (!gltf_name(n).empty()) {
      arrays.push_back(ca.base(n));
      exported.push_back(n);
    }
  const std::vector<std::string> morph_corners = morph_corner_names(mesh, targets);
  for (const auto& n : morph_corners) arrays.push_back(ca.base(n));
  const GltfVertices vertices = unweld(mesh, arrays);
  const std::size_t n = vertices.vertex.size();
  reserve_bin(primitive_bound(mesh, n));
  [[maybe_unused]] const std::size_t cap_before = bin_.capacity();  // primitive_bound held: no growth below
  json attributes = json::object();
  {
    std::size_t at = 0;
    const int accessor = add_accessor<float>(n, 3, kFloat, "VEC3", kArrayBuffer, &at);
    float* pos = data<float>(at);
    each(n, [&](std::size_t i) {
      const auto& p = mesh.positions()[vertices.vertex[i]];
      for (int c = 0; c < 3; ++c) pos[3 * i + std::size_t(c)] = p[c];
    });
    add_min_max<float>(accessor, at, n, 3);
    attributes["POSITION"] = accessor;
  }
  write_influences(mesh, vertices.vertex, attributes);
  for (std::size_t a = 0; a < exported.size(); ++a) write_corner_attribute(mesh, exported[a], *arrays[a], vertices.corner, attributes);
  out["attributes"] = attributes;
  if (targets > 0) out["targets"] = write_targets(mesh, vertices, targets, morph_corners);
  const auto& indices = vertices.indices;
  if (n <= 65535) {
    std::size_t at = 0;
    out["indices"] = add_accessor<std::uint16_t>(indices.size(), 1, kUnsignedShort, "SCALAR", kElementArrayBuffer, &at);
    std::uint16_t* idx16 = data<std::uint16_t>(at);
    each(indices.size(), [&](std::size_t i) { idx16[i] = static_cast<std::uint16_t>(indices[i]); });
  } else {
    out["indices"] = add_accessor(indices, 1, kUnsignedInt, "SCALAR", kElementArrayBuffer);
  }
  out["mode"] = 4;
  if (prim.material >= 0 && static_cast<std::size_t>(prim.material) < model_.materials.size()) out["material"] = prim.material;
  if (!prim.extras_json.empty()) out["extras"] = parse_or(prim.extras_json, json::object());
  assert(bin_.capacity() == cap_before && "primitive_bound too small: the binary buffer moved mid-primitive");
}

// The primitive's `targets`: each target's POSITION deltas per glTF vertex (with the min/max glTF
// requires), and its NORMAL / TANGENT deltas where `morph_corners` names them. A delta that is not
// finite is written as 0.
json Writer::write_targets(const SurfaceMesh& mesh, const GltfVertices& vertices, std::size_t targets,
                           const std::vector<std::string>& morph_corners) {
  const std::size_t n = vertices.vertex.size();
  auto write = [&](const std::vector<glm::vec3>& d, const auto& from, bool minmax) {
    std::size_t at = 0;
    const int accessor = add_accessor<float>(n, 3, kFloat, "VEC3", kArrayBuffer, &at);
    float* out = data<float>(at);
    each(n, [&](std::size_t i) {
      for (int c = 0; c < 3; ++c) {
        const float v = d[from[i]][c];
        out[3 * i + std::size_t(c)] = std::isfinite(v) ? v : 0.0f;
      }
    });
    if (minmax) add_min_max<float>(accessor, at, n, 3);
    return accessor;
  };
  json out = json::array();
  for (std::size_t t = 0; t < targets; ++t) {
    const int i = static_cast<int>(t);
    json target = {{"POSITION", write(mesh.vertex_attrs().get<glm::vec3>(attr::morph_position_name(i)).data(), vertices.vertex, true)}};
    const std::string normal = attr::morph_normal_name(i), tangent = attr::morph_tangent_name(i);
    const auto has = [&](const std::string& name) {
      return std::find(morph_corners.begin(), morph_corners.end(), name) != morph_corners.end();
    };
    if (has(normal)) target["NORMAL"] = write(mesh.corner_attrs().get<glm::vec3>(normal).data(), vertices.corner, false);
    if (has(tangent)) target["TANGENT"] = write(mesh.corner_attrs().get<glm::vec3>(tangent).data(), vertices.corner, false);
    out.push_back(target);
  }
  return out;
}

// Skin influences of each glTF vertex, renormalised; zero-weight slots name joint 0.
void Writer::write_influences(const SurfaceMesh& mesh, const Indices& out_vertex, json& attributes) {
  const std::size_t n = out_vertex.size();
  const auto& va = mesh.vertex_attrs();
  const char* jn[2] = {attr::kJoints0, attr::kJoints1};
  const char* wn[2] = {attr::kWeights0, attr::kWeights1};
  int sets = 0;
  while (sets < 2 && va.find<glm::u16vec4>(jn[sets]) && va.find<glm::vec4>(wn[sets])) ++sets;
  if (sets > 0) {
    // The accessors in the file's order (JOINTS_0, WEIGHTS_0, JOINTS_1, ...), then one pass fills them.
    std::size_t joints_at[2] = {}, weights_at[2] = {};
    for (int s = 0; s < sets; ++s) {
      attributes["JOINTS_" + std::to_string(s)] = add_accessor<std::uint16_t>(n, 4, kUnsignedShort, "VEC4", kArrayBuffer, &joints_at[s]);
      attributes["WEIGHTS_" + std::to_string(s)] = add_accessor<float>(n, 4, kFloat, "VEC4", kArrayBuffer, &weights_at[s]);
    }
    std::uint16_t* joints[2] = {};
    float* weights[2] = {};
    for (int s = 0; s < sets; ++s) {
      joints[s] = data<std::uint16_t>(joints_at[s]);
      weights[s] = data<float>(weights_at[s]);
    }
    const glm::u16vec4* in_joints[2] = {};
    const glm::vec4* in_weights[2] = {};
    for (int s = 0; s < sets; ++s) {
      in_joints[s] = va.get<glm::u16vec4>(jn[s]).data().data();
      in_weights[s] = va.get<glm::vec4>(wn[s]).data().data();
    }
    each(n, [&](std::size_t i) {
      std::uint16_t jj[8] = {};
      float ww[8] = {};
      for (int s = 0; s < sets; ++s)
        for (int c = 0; c < 4; ++c) {
          jj[4 * s + c] = in_joints[s][out_vertex[i]][c];
          ww[4 * s + c] = in_weights[s][out_vertex[i]][c];
        }
      normalize_influences(jj, ww, 4 * sets);
      for (int s = 0; s < sets; ++s)
        for (int c = 0; c < 4; ++c) {
          joints[s][4 * i + std::size_t(c)] = jj[4 * s + c];
          weights[s][4 * i + std::size_t(c)] = ww[4 * s + c];
        }
    });
  }
}

// One exported corner attribute, per glTF vertex (normals and tangents made unit, colours clamped).
void Writer::write_corner_attribute(const SurfaceMesh& mesh, const std::string& name, const AttributeArrayBase& corner_array,
                                    const Indices& out_corner, json& attributes) {
  const std::size_t n = out_corner.size();
  const auto* array = &corner_array;
  const std::string gname = gltf_name(name);
  if (array->type() == typeid(glm::vec2)) {
    const auto& d = static_cast<const AttributeArray<glm::vec2>*>(array)->data();
    std::size_t at = 0;
    attributes[gname] = add_accessor<float>(n, 2, kFloat, "VEC2", kArrayBuffer, &at);
    float* out_data = data<float>(at);
    each(n, [&](std::size_t i) {
      out_data[2 * i] = d[out_corner[i]].x;
      out_data[2 * i + 1] = d[out_corner[i]].y;
    });
  } else if (array->type() == typeid(glm::vec3)) {
    const auto& d = static_cast<const AttributeArray<glm::vec3>*>(array)->data();
    std::size_t at = 0;
    attributes[gname] = add_accessor<float>(n, 3, kFloat, "VEC3", kArrayBuffer, &at);
    float* out_data = data<float>(at);
    const bool normal = gname == "NORMAL";
    each(n, [&](std::size_t i) {
      glm::vec3 v = d[out_corner[i]];
      if (normal) {
        const float len = glm::length(v);
        if (len > 1e-12f && std::isfinite(len)) {
          if (!unit_enough(len)) v /= len;
        } else {  // a zero normal is invalid glTF: use the face's normal
          const auto& t = mesh.face(FaceId(out_corner[i] / 3));
          const glm::vec3 fn = glm::cross(mesh.position(t[1]) - mesh.position(t[0]), mesh.position(t[2]) - mesh.position(t[0]));
          const float fl = glm::length(fn);
          v = fl > 0.0f ? fn / fl : glm::vec3(0.0f, 0.0f, 1.0f);
        }
      }
      for (int c = 0; c < 3; ++c) out_data[3 * i + std::size_t(c)] = v[c];
    });
  } else if (array->type() == typeid(glm::vec4)) {
    const auto& d = static_cast<const AttributeArray<glm::vec4>*>(array)->data();
    std::size_t at = 0;
    attributes[gname] = add_accessor<float>(n, 4, kFloat, "VEC4", kArrayBuffer, &at);
    float* out_data = data<float>(at);
    const bool tangent = gname == "TANGENT", colour = gname == "COLOR_0";
    each(n, [&](std::size_t i) {
      glm::vec4 v = d[out_corner[i]];
      if (tangent) {
        glm::vec3 xyz(v);
        const float len = glm::length(xyz);
        if (!(len > 1e-12f && std::isfinite(len))) xyz = glm::vec3(1.0f, 0.0f, 0.0f);
        else if (!unit_enough(len)) xyz /= len;
        v = glm::vec4(xyz, v.w < 0.0f ? -1.0f : 1.0f);
      } else if (colour) {
        v = glm::clamp(v, glm::vec4(0.0f), glm::vec4(1.0f));
      }
      for (int c = 0; c < 4; ++c) out_data[4 * i + std::size_t(c)] = v[c];
    });
  }
}

void Writer::write_meshes() {
  mesh_map_.assign(model_.meshes.size(), -1);
  mesh_targets_.assign(model_.meshes.size(), 0);
  for (std::size_t m = 0; m < model_.meshes.size(); ++m) {
    const auto& mesh = model_.meshes[m];
    json out = json::object();
    if (!mesh.name.empty()) out["name"] = mesh.name;
    // glTF wants as many targets in every primitive: the ones all written primitives carry.
    std::size_t targets = mesh.target_count();
    for (const auto& prim : mesh.primitives)
      if (prim.mesh.face_count() > 0) targets = std::min(targets, morph_targets(prim.mesh));
    for (const auto& prim : mesh.primitives) {
      if (prim.mesh.face_count() == 0) continue;  // glTF has no empty primitives
      json p = json::object();
      write_primitive(prim, targets, p);
      out["primitives"].push_back(p);
    }
    if (!out.contains("primitives")) continue;  // every primitive was empty: drop the mesh
    if (targets > 0) out["weights"] = std::vector<float>(mesh.weights.begin(), mesh.weights.begin() + std::ptrdiff_t(targets));
    if (!mesh.extras_json.empty()) out["extras"] = parse_or(mesh.extras_json, json::object());
    mesh_map_[m] = static_cast<int>(doc_["meshes"].size());
    mesh_targets_[m] = targets;
    doc_["meshes"].push_back(out);
  }
}

void Writer::write_skins() {
  for (const auto& s : model_.skins) {
    json out = {{"joints", s.joints}};
    if (!s.name.empty()) out["name"] = s.name;
    if (s.skeleton >= 0) out["skeleton"] = s.skeleton;
    std::vector<float> m(16 * s.joints.size());
    for (std::size_t j = 0; j < s.joints.size(); ++j) {
      const glm::mat4 ibm = j < s.inverse_bind_matrices.size() ? s.inverse_bind_matrices[j] : glm::mat4(1.0f);
      for (int k = 0; k < 16; ++k) m[16 * j + std::size_t(k)] = ibm[k / 4][k % 4];
    }
    if (!s.joints.empty()) out["inverseBindMatrices"] = add_accessor(m, 16, kFloat, "MAT4", 0);
    doc_["skins"].push_back(out);
  }
}

void Writer::write_animations() {
  for (const auto& a : model_.animations) {
    json out = json::object();
    if (!a.name.empty()) out["name"] = a.name;
    // A sampler is written once per kind of channel using it (weights are SCALAR, the rest vectors).
    std::vector<int> used(a.samplers.size(), -1), used_weights(a.samplers.size(), -1);
    for (const auto& ch : a.channels) {
      if (ch.sampler < 0 || static_cast<std::size_t>(ch.sampler) >= a.samplers.size()) continue;
      const auto& s = a.samplers[ch.sampler];
      if (s.input.empty()) continue;
      const bool weights = ch.path == AnimationPath::Weights;
      if (weights && !drives_written_targets(ch.node, s.components)) continue;
      std::vector<int>& slot = weights ? used_weights : used;
      if (slot[ch.sampler] < 0) {
        std::vector<float> output = s.output;
        if (ch.path == AnimationPath::Rotation && s.interpolation != Interpolation::CubicSpline)
          for (std::size_t k = 0; k + 3 < output.size(); k += 4) {
            glm::vec4 q(output[k], output[k + 1], output[k + 2], output[k + 3]);
            const float len = glm::length(q);
            if (!(len > 0.0f)) q = glm::vec4(0, 0, 0, 1);
            else if (!unit_enough(len)) q /= len;
            for (int c = 0; c < 4; ++c) output[k + std::size_t(c)] = q[c];
          }
        const int comps = !weights && (s.components == 4 || s.components == 3) ? s.components : 1;
        const char* type = comps == 4 ? "VEC4" : comps == 3 ? "VEC3" : "SCALAR";
        json sampler = {{"input", add_accessor(s.input, 1, kFloat, "SCALAR", 0, true)},
                        {"output", add_accessor(output, comps, kFloat, type, 0)},
                        {"interpolation", s.interpolation == Interpolation::Step          ? "STEP"
                                          : s.interpolation == Interpolation::CubicSpline ? "CUBICSPLINE"
                                                                                          : "LINEAR"}};
        slot[ch.sampler] = static_cast<int>(out["samplers"].size());
        out["samplers"].push_back(sampler);
      }
      static const char* paths[] = {"translation", "rotation", "scale", "weights"};
      out["channels"].push_back({{"sampler", slot[ch.sampler]}, {"target", {{"node", ch.node}, {"path", paths[int(ch.path)]}}}});
    }
    if (!out.contains("channels")) continue;
    doc_["animations"].push_back(out);
  }
}

// True when `node` draws a written mesh with `components` morph targets: only then may a channel
// drive its weights (a mesh an operation emptied, or that lost its targets, takes its channels along).
bool Writer::drives_written_targets(int node, int components) const {
  if (node < 0 || static_cast<std::size_t>(node) >= model_.nodes.size()) return false;
  const int mesh = model_.nodes[std::size_t(node)].mesh;
  if (mesh < 0 || static_cast<std::size_t>(mesh) >= mesh_map_.size() || mesh_map_[std::size_t(mesh)] < 0) return false;
  return components > 0 && mesh_targets_[std::size_t(mesh)] == static_cast<std::size_t>(components);
}

void Writer::write_nodes() {
  for (const auto& n : model_.nodes) {
    json out = json::object();
    if (!n.name.empty()) out["name"] = n.name;
    if (!n.children.empty()) out["children"] = n.children;
    if (n.matrix) {
      std::vector<float> m(16);
      for (int k = 0; k < 16; ++k) m[std::size_t(k)] = (*n.matrix)[k / 4][k % 4];
      if (*n.matrix != glm::mat4(1.0f)) out["matrix"] = m;
    } else {
      if (n.translation != glm::vec3(0.0f)) out["translation"] = {n.translation.x, n.translation.y, n.translation.z};
      const float len = glm::length(n.rotation);
      const glm::quat q = unit_enough(len) ? n.rotation : glm::normalize(n.rotation);
      if (q != glm::quat(1.0f, 0.0f, 0.0f, 0.0f)) out["rotation"] = {q.x, q.y, q.z, q.w};
      if (n.scale != glm::vec3(1.0f)) out["scale"] = {n.scale.x, n.scale.y, n.scale.z};
    }
    const int mesh = n.mesh >= 0 && static_cast<std::size_t>(n.mesh) < mesh_map_.size() ? mesh_map_[n.mesh] : -1;
    if (mesh >= 0) {
      out["mesh"] = mesh;
      if (n.skin >= 0) out["skin"] = n.skin;
      // One weight per written target (missing ones 0): glTF wants the counts equal.
      const std::size_t targets = mesh_targets_[std::size_t(n.mesh)];
      if (!n.weights.empty() && targets > 0) {
        std::vector<float> w(targets, 0.0f);
        std::copy_n(n.weights.begin(), std::min(targets, n.weights.size()), w.begin());
        out["weights"] = w;
      }
    }
    if (n.camera >= 0) out["camera"] = n.camera;
    if (!n.extras_json.empty()) out["extras"] = parse_or(n.extras_json, json::object());
    if (!n.extensions_json.empty()) out["extensions"] = parse_or(n.extensions_json, json::object());
    doc_["nodes"].push_back(out);
  }
}

void Writer::write_images() {
  for (const auto& img : model_.images) {
    std::size_t at = 0;
    json out = {{"bufferView", add_view(img.data.size(), 0, &at)}, {"mimeType", img.mime_type}};
    if (!img.data.empty()) std::memcpy(bin_.data() + at, img.data.data(), img.data.size());
    if (!img.name.empty()) out["name"] = img.name;
    doc_["images"].push_back(out);
  }
}

// Room in the binary buffer for `bytes` more (a primitive's bound) and what the skins, animations
// and images add (tail_, tail_bound), so a primitive is written without the buffer growing
// (write_primitive asserts it) and the tail fits after the last one. The first primitive's
// reserve copies nothing (the buffer is empty); a later one that does not fit copies what the
// earlier ones wrote, and then grows by half at least so that many primitives copy it few times.
// Sized by what is written, not by a bound of all the corners, it stays within what the heap
// keeps for the next export (keep_freed_memory: blocks up to 1 GiB).
void Writer::reserve_bin(std::size_t bytes) {
  const std::size_t need = bin_.size() + bytes + tail_;
  if (need > bin_.capacity()) bin_.reserve(std::max(need, bin_.capacity() + bin_.capacity() / 2));
}

// At least what the skins, animations and images add to the binary buffer.
std::size_t Writer::tail_bound() const {
  std::size_t bytes = 1024;
  for (const auto& s : model_.skins) bytes += 64 * s.joints.size() + 4;
  for (const auto& a : model_.animations)
    for (const auto& sm : a.samplers) bytes += 4 * (sm.input.size() + sm.output.size()) + 8;
  for (const auto& img : model_.images) bytes += img.data.size() + 4;
  return bytes;
}

std::vector<unsigned char> Writer::write(bool glb) {
  write_asset();
  tail_ = tail_bound();
  write_meshes();
  reserve_bin(0);  // the tail's room: already there when a primitive was written
  write_nodes();
  write_skins();
  write_animations();
  write_images();
  write_passthrough();
  write_extensions_and_extras();
  write_buffer(glb);
  compress_document(doc_, bin_, options_.compression, glb);
  if (!glb) {
    const std::string text = options_.pretty ? doc_.dump(2) : doc_.dump();
    return std::vector<unsigned char>(text.begin(), text.end());
  }
  return glb_start(doc_, bin_.size());
}

void Writer::write_asset() {
  json asset = {{"version", "2.0"}, {"generator", options_.generator}};
  if (!model_.asset_copyright.empty()) asset["copyright"] = model_.asset_copyright;
  if (!model_.asset_extras_json.empty()) asset["extras"] = parse_or(model_.asset_extras_json, json::object());
  doc_["asset"] = asset;
}

// The objects carried through as read (materials, textures, samplers, cameras) and the scenes.
void Writer::write_passthrough() {
  auto passthrough = [&](const char* key, const std::vector<PassthroughObject>& list) {
    for (const auto& o : list) doc_[key].push_back(parse_or(o.json, json::object()));
  };
  passthrough("materials", model_.materials);
  passthrough("textures", model_.textures);
  passthrough("samplers", model_.samplers);
  passthrough("cameras", model_.cameras);
  if (!model_.scenes.empty()) {
    for (const auto& roots : model_.scenes) doc_["scenes"].push_back({{"nodes", roots}});
    doc_["scene"] = std::clamp(model_.default_scene, 0, static_cast<int>(model_.scenes.size()) - 1);
  }
}

void Writer::write_extensions_and_extras() {
  // Extensions that only concern the original encoding no longer apply to what we write.
  auto keep_extension = [](const std::string& e) {
    return e != "KHR_mesh_quantization" && e != "KHR_draco_mesh_compression" && e != "EXT_meshopt_compression";
  };
  for (const auto& e : model_.extensions_used)
    if (keep_extension(e)) doc_["extensionsUsed"].push_back(e);
  for (const auto& e : model_.extensions_required)
    if (keep_extension(e)) doc_["extensionsRequired"].push_back(e);
  if (!model_.extras_json.empty()) doc_["extras"] = parse_or(model_.extras_json, json::object());
  if (!model_.extensions_json.empty()) doc_["extensions"] = parse_or(model_.extensions_json, json::object());
}

// The binary buffer padded to 4 bytes and declared (in a .gltf, embedded as base64).
void Writer::write_buffer(bool glb) {
  while (bin_.size() % 4) bin_.push_back(0);
  if (!bin_.empty()) {
    json buffer = {{"byteLength", bin_.size()}};
    if (!glb) buffer["uri"] = "data:application/octet-stream;base64," + base64_encode(bin_.data(), bin_.size());
    doc_["buffers"] = json::array({buffer});
  }
}

}  // namespace

void write_gltf(const Model& model, const std::string& path, const ExportOptions& options) {
  const bool glb = has_extension(path, ".glb");
  if (!glb && !has_extension(path, ".gltf"))
    throw Error(ErrorCode::InvalidArgument, path + ": unknown output format (use .glb or .gltf)");
  std::vector<unsigned char> bytes;
  Writer writer(model, options);
  try {
    bytes = writer.write(glb);
  } catch (const json::exception& e) {
    throw Error(ErrorCode::InvariantViolated, path + ": could not encode the model (" + e.what() + ")");
  } catch (const Error& e) {  // a codec of compress_document
    throw Error(e.code(), path + ": " + e.what());
  }
  std::vector<ByteSpan> parts{{bytes.data(), bytes.size()}};
  if (glb && !writer.bin().empty()) parts.push_back({writer.bin().data(), writer.bin().size()});
  write_file_atomic(path, parts);
}

}  // namespace deepcut
