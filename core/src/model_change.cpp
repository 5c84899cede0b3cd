// SPDX-License-Identifier: MIT
// diff_models: what a step changed, found by comparing the models before and after it (the
// reference the recorded changes are tested against).
#include "deepcut/core/model_change.h"

#include <algorithm>
#include <cstring>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "deepcut/core/model.h"
#include "model_parts_equal.h"

namespace deepcut {
namespace {

// Floats are compared bit for bit, not with ==: -0.0 and +0.0 are written differently (a step
// that turns one into the other changes the model's bytes, and an undo record sharing one for the
// other would not give them back), and a NaN equals itself.
template <class T>
bool same_bits(const T& a, const T& b) {
  static_assert(std::is_trivially_copyable_v<T>);
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  static_assert(std::is_trivially_copyable_v<T>);
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

template <class T>
bool same_bits(const std::optional<T>& a, const std::optional<T>& b) {
  return a.has_value() == b.has_value() && (!a || same_bits(*a, *b));
}

bool same(const Node& a, const Node& b) {
  return a.name == b.name && a.children == b.children && same_bits(a.translation, b.translation) &&
         same_bits(a.rotation, b.rotation) && same_bits(a.scale, b.scale) && same_bits(a.matrix, b.matrix) &&
         a.mesh == b.mesh && a.skin == b.skin && a.camera == b.camera && same_bits(a.weights, b.weights) &&
         a.extras_json == b.extras_json && a.extensions_json == b.extensions_json;
}

bool same(const Skin& a, const Skin& b) {
  return a.name == b.name && a.joints == b.joints &&
         same_bits(a.inverse_bind_matrices, b.inverse_bind_matrices) &&
         a.had_inverse_bind_matrices == b.had_inverse_bind_matrices && a.skeleton == b.skeleton;
}

bool same(const Animation& a, const Animation& b) {
  if (a.name != b.name || a.samplers.size() != b.samplers.size() || a.channels.size() != b.channels.size())
    return false;
  for (std::size_t i = 0; i < a.samplers.size(); ++i) {
    const AnimationSampler &x = a.samplers[i], &y = b.samplers[i];
    if (!same_bits(x.input, y.input) || !same_bits(x.output, y.output) || x.components != y.components ||
        x.interpolation != y.interpolation)
      return false;
  }
  for (std::size_t i = 0; i < a.channels.size(); ++i) {
    const AnimationChannel &x = a.channels[i], &y = b.channels[i];
    if (x.sampler != y.sampler || x.node != y.node || x.path != y.path) return false;
  }
  return true;
}

bool same(const PassthroughObject& a, const PassthroughObject& b) { return a.name == b.name && a.json == b.json; }

bool same(const Image& a, const Image& b) {
  return a.name == b.name && a.mime_type == b.mime_type && a.data == b.data;
}

bool same(const ImportProblem& a, const ImportProblem& b) {
  return a.kind == b.kind && a.message == b.message && a.count == b.count && a.places == b.places;
}

bool same_layout(const AttributeSet& a, const AttributeSet& b) {
  const std::vector<std::string> names = a.names();
  if (names != b.names()) return false;
  for (const std::string& n : names)
    if (a.base(n)->type() != b.base(n)->type()) return false;
  return true;
}

bool same_layout(const SurfaceMesh& a, const SurfaceMesh& b) {
  return same_layout(a.vertex_attrs(), b.vertex_attrs()) && same_layout(a.face_attrs(), b.face_attrs()) &&
         same_layout(a.corner_attrs(), b.corner_attrs());
}

bool same(const Mesh& a, const Mesh& b) {
  if (a.name != b.name || a.extras_json != b.extras_json || !same_bits(a.weights, b.weights) ||
      a.target_names != b.target_names || a.primitives.size() != b.primitives.size())
    return false;
  for (std::size_t i = 0; i < a.primitives.size(); ++i) {
    const Primitive &x = a.primitives[i], &y = b.primitives[i];
    if (x.material != y.material || x.extras_json != y.extras_json || x.gltf_vertices != y.gltf_vertices ||
        x.welded_merged != y.welded_merged || !same_layout(x.mesh, y.mesh))
      return false;
  }
  return true;
}

template <class T>
bool same_all(const std::vector<T>& a, const std::vector<T>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same(a[i], b[i])) return false;
  return true;
}

/// Marks in `changed` the elements below `n` whose bytes differ in some array of the two sets
/// (same layout).
void mark_differing(const AttributeSet& a, const AttributeSet& b, std::size_t n, std::size_t group,
                    std::vector<std::uint8_t>& changed) {
  for (const std::string& name : a.names()) {
    const AttributeArrayBase* x = a.base(name);
    const AttributeArrayBase* y = b.base(name);
    if (n * group == 0) continue;
    const std::size_t bytes = x->element_bytes() * group;
    const auto* px = static_cast<const unsigned char*>(x->element_data(0));
    const auto* py = static_cast<const unsigned char*>(y->element_data(0));
    for (std::size_t i = 0; i < n; ++i)
      if (!changed[i] && std::memcmp(px + i * bytes, py + i * bytes, bytes) != 0) changed[i] = 1;
  }
}

std::vector<std::uint32_t> listed(const std::vector<std::uint8_t>& changed) {
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < changed.size(); ++i)
    if (changed[i]) out.push_back(static_cast<std::uint32_t>(i));
  return out;
}

}  // namespace

bool detail::same_part(const Node& a, const Node& b) { return same(a, b); }
bool detail::same_part(const Mesh& a, const Mesh& b) { return same(a, b); }

bool same_structure(const Model& a, const Model& b, bool images) {
  return same_all(a.nodes, b.nodes) && a.scenes == b.scenes && a.default_scene == b.default_scene &&
         same_all(a.skins, b.skins) && same_all(a.animations, b.animations) && same_all(a.meshes, b.meshes) &&
         (!images || same_all(a.images, b.images)) && same_all(a.materials, b.materials) && same_all(a.textures, b.textures) &&
         same_all(a.samplers, b.samplers) && same_all(a.cameras, b.cameras) &&
         a.extensions_used == b.extensions_used && a.extensions_required == b.extensions_required &&
         a.extensions_json == b.extensions_json && a.asset_copyright == b.asset_copyright &&
         a.asset_extras_json == b.asset_extras_json && same_all(a.import_problems, b.import_problems);
}

bool diff_meshes(const SurfaceMesh& before, const SurfaceMesh& after, PrimitiveChange& out) {
  if (!same_layout(before, after)) return false;
  out.vertices_before = before.vertex_count();
  out.faces_before = before.face_slots();
  const std::size_t nv = std::min(before.vertex_count(), after.vertex_count());
  const std::size_t nf = std::min(before.face_slots(), after.face_slots());
  std::vector<std::uint8_t> vchanged(nv, 0), fchanged(nf, 0);
  mark_differing(before.vertex_attrs(), after.vertex_attrs(), nv, 1, vchanged);
  mark_differing(before.face_attrs(), after.face_attrs(), nf, 1, fchanged);
  mark_differing(before.corner_attrs(), after.corner_attrs(), nf, 3, fchanged);
  for (std::size_t f = 0; f < nf; ++f)
    if (before.faces()[f] != after.faces()[f] || before.is_deleted(FaceId(static_cast<std::uint32_t>(f))) !=
                                                     after.is_deleted(FaceId(static_cast<std::uint32_t>(f))))
      fchanged[f] = 1;
  out.vertices.clear();
  out.faces.clear();
  for (std::uint32_t v : listed(vchanged)) out.vertices.push_back(VertexId(v));
  for (std::uint32_t f : listed(fchanged)) out.faces.push_back(FaceId(f));
  return true;
}

ModelChange diff_models(const Model& before, const Model& after) {
  ModelChange change;
  if (!same_structure(before, after)) {
    change.structure = true;
    return change;
  }
  for (std::size_t mi = 0; mi < before.meshes.size(); ++mi)
    for (std::size_t pi = 0; pi < before.meshes[mi].primitives.size(); ++pi) {
      PrimitiveChange p;
      diff_meshes(before.meshes[mi].primitives[pi].mesh, after.meshes[mi].primitives[pi].mesh, p);
      const SurfaceMesh& now = after.meshes[mi].primitives[pi].mesh;
      if (p.vertices.empty() && p.faces.empty() && p.vertices_before == now.vertex_count() &&
          p.faces_before == now.face_slots())
        continue;
      p.mesh = static_cast<int>(mi);
      p.primitive = static_cast<int>(pi);
      change.primitives.push_back(std::move(p));
    }
  return change;
}

}  // namespace deepcut
