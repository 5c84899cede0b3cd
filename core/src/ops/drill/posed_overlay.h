// SPDX-License-Identifier: MIT
#pragma once
// The drill's posed positions: the input's posed positions, overlaid with the positions of the
// vertices the drill adds (in double precision, in id order) and of the old vertices it moves,
// and the way back to bind space for new vertices. Private to the drill.

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/ops/drill.h"
#include "ops/drill/cylinder_section.h"

namespace deepcut::drill {

class PosedOverlay {
 public:
  /// `posed` holds one position per vertex below `first_new`; `unpose` may be empty (posed ==
  /// bind). `posed` is referenced, not copied.
  PosedOverlay(const std::vector<glm::vec3>& posed, std::uint32_t first_new, const Unposer& unpose)
      : posed_(posed), unpose_(unpose), first_new_(first_new) {}

  /// Posed position of `v` (added, moved or input).
  glm::dvec3 operator()(VertexId v) const {
    if (v.index >= first_new_) return added_[v.index - first_new_];
    if (!moved_.empty()) {
      const auto it = std::lower_bound(moved_.begin(), moved_.end(), std::make_pair(v.index, glm::dvec3(-kInf)),
                                       [](const auto& x, const auto& y) { return x.first < y.first; });
      if (it != moved_.end() && it->first == v.index) return it->second;
    }
    return glm::dvec3(posed_[v.index]);
  }
  /// Posed position of the added vertex `v` (v >= first_new).
  const glm::dvec3& added(VertexId v) const { return added_[v.index - first_new_]; }

  std::uint32_t first_new() const { return first_new_; }
  const Unposer& unpose() const { return unpose_; }
  const std::vector<glm::vec3>& input() const { return posed_; }

  /// The next added vertex is at `p`.
  void push(const glm::dvec3& p) { added_.push_back(p); }
  /// Old vertex `v` (ids in increasing order) now lies at `p`.
  void move(std::uint32_t v, const glm::dvec3& p) { moved_.emplace_back(v, p); }
  const std::vector<glm::dvec3>& added_positions() const { return added_; }
  const std::vector<std::pair<std::uint32_t, glm::dvec3>>& moved() const { return moved_; }

  // Skinning is not linear in the blended weights, so a new vertex interpolated in bind space
  // would land beside its posed target: with an unposer it is placed by inverse skinning.
  void place(MeshEditor& editor, VertexId v, const glm::dvec3& target) const {
    if (!unpose_) return;
    const glm::vec3 bind = unpose_(editor.mesh(), v, glm::vec3(target));
    if (bind != editor.mesh().position(v)) editor.move_vertex(v, bind);
  }

 private:
  const std::vector<glm::vec3>& posed_;
  Unposer unpose_;
  std::uint32_t first_new_ = 0;
  std::vector<glm::dvec3> added_;
  // Old vertices moved onto the cylinder: (index, new posed), by index.
  std::vector<std::pair<std::uint32_t, glm::dvec3>> moved_;
};

}  // namespace deepcut::drill
