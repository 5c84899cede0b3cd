// SPDX-License-Identifier: MIT
#include "deepcut/core/morph.h"

#include <algorithm>

namespace deepcut {

int morph_target_count(const SurfaceMesh& mesh) {
  int n = 0;
  while (mesh.vertex_attrs().find<glm::vec3>(attr::morph_position_name(n))) ++n;
  return n;
}

std::vector<float> default_morph_weights(const Model& model, int node) {
  if (node < 0 || static_cast<std::size_t>(node) >= model.nodes.size()) return {};
  const Node& n = model.nodes[static_cast<std::size_t>(node)];
  if (n.mesh < 0 || static_cast<std::size_t>(n.mesh) >= model.meshes.size()) return {};
  const Mesh& mesh = model.meshes[static_cast<std::size_t>(n.mesh)];
  if (mesh.target_count() == 0) return {};
  return n.weights.size() == mesh.target_count() ? n.weights : mesh.weights;
}

MorphBlend::MorphBlend(const SurfaceMesh& mesh, const std::vector<float>& weights) {
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (weights[i] == 0.0f) continue;
    const int target = static_cast<int>(i);
    const auto* position = mesh.vertex_attrs().find<glm::vec3>(attr::morph_position_name(target));
    if (!position) break;  // targets are numbered from 0 without gaps
    targets_.push_back({weights[i], position, mesh.corner_attrs().find<glm::vec3>(attr::morph_normal_name(target))});
  }
}

std::vector<AttributeArray<glm::vec3>*> corner_morph_deltas(SurfaceMesh& mesh) {
  std::vector<AttributeArray<glm::vec3>*> out;
  const int targets = morph_target_count(mesh);
  for (int i = 0; i < targets; ++i) {
    if (auto* n = mesh.corner_attrs().find<glm::vec3>(attr::morph_normal_name(i))) out.push_back(n);
    if (auto* t = mesh.corner_attrs().find<glm::vec3>(attr::morph_tangent_name(i))) out.push_back(t);
  }
  return out;
}

std::vector<glm::vec3> morphed_positions(const SurfaceMesh& mesh, const std::vector<float>& weights) {
  const MorphBlend blend(mesh, weights);
  std::vector<glm::vec3> out = mesh.positions();
  if (!blend.active()) return out;
  for (std::size_t v = 0; v < out.size(); ++v) out[v] = blend.position(v, out[v]);
  return out;
}

}  // namespace deepcut
