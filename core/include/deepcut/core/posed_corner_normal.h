// SPDX-License-Identifier: MIT
#pragma once
/// @file posed_corner_normal.h
/// The one kernel of every posed corner normal (PosedMesh::corner_normals and its followers),
/// inline so that a caller that needs only some corners' normals (the studio's first frame
/// after an open: one per drawn point, not one per corner) computes the same bits without a
/// per-corner array.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "deepcut/core/morph.h"
#include "deepcut/core/posed_model.h"

namespace deepcut {

/// The normal map of a vertex's linear bind-to-world map: its inverse transpose.
inline glm::mat3 posed_normal_map(const glm::mat3& linear) { return glm::transpose(glm::inverse(linear)); }

/// World normal of corner `c` (of a face whose corner is vertex v): its normal plus its morph
/// deltas, through v's normal map (`map` null: the identity), renormalised.
inline glm::vec3 posed_corner_normal(const MorphBlend& morph, const AttributeArray<glm::vec3>& normals,
                                     std::size_t c, const glm::mat3* map) {
  const glm::vec3 m = morph.normal(c, normals[c]);
  const glm::vec3 n = map ? *map * m : m;
  const float len = glm::length(n);
  return len > 0.0f ? n / len : n;
}

/// The posed normal of any corner of `surface` posed by `pose`, one at a time: equal, bit for
/// bit, to that corner's entry of pose.corner_normals(surface). Both must outlive it.
class CornerNormalPoser {
 public:
  CornerNormalPoser(const PosedMesh& pose, const SurfaceMesh& surface)
      : normals_(surface.corner_attrs().find<glm::vec3>(attr::kNormal)),
        linear_(pose.linear),
        morph_(surface, pose.weights) {}
  /// False when the mesh has no normals (then corner_normals is empty too).
  bool has_normals() const { return normals_ != nullptr; }
  /// The posed normal of corner `c`, whose vertex is `v`. @pre has_normals().
  glm::vec3 operator()(std::uint32_t v, std::size_t c) const {
    if (linear_.empty()) return posed_corner_normal(morph_, *normals_, c, nullptr);
    const glm::mat3 map = posed_normal_map(linear_[v]);
    return posed_corner_normal(morph_, *normals_, c, &map);
  }

 private:
  const AttributeArray<glm::vec3>* normals_;
  const UninitVector<glm::mat3>& linear_;
  MorphBlend morph_;
};

}  // namespace deepcut
