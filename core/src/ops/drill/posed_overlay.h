// SPDX-License-Identifier: MIT
#pragma once
// The drill's posed positions (the input's, overlaid with those of the vertices the drill adds
// and moves, in double precision: ops/common/posed_overlay.h) and the way back to bind space for
// new vertices. Private to the drill.

#include <functional>
#include <glm/glm.hpp>
#include <utility>
#include <vector>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/ops/drill.h"
#include "ops/common/placement.h"
#include "ops/common/posed_overlay.h"

namespace deepcut::drill {

/// Maps the posed position of a new vertex back to bind space (ops/common/placement.h).
using Unposer = detail::Unposer;

class PosedOverlay : public detail::PosedOverlay<glm::dvec3> {
 public:
  /// `posed`: one position per vertex of the mesh as the drill starts (kept by reference);
  /// `unpose` may be empty (posed == bind).
  PosedOverlay(const std::vector<glm::vec3>& posed, Unposer unpose)
      : detail::PosedOverlay<glm::dvec3>(posed), unpose_(std::move(unpose)) {}

  const Unposer& unpose() const { return unpose_; }

  // Skinning is not linear in the blended weights, so a new vertex interpolated in bind space
  // would land beside its posed target: with an unposer it is placed by inverse skinning.
  void place(MeshEditor& editor, VertexId v, const glm::dvec3& target) const {
    if (!unpose_) return;
    const glm::vec3 bind = unpose_(editor.mesh(), v, glm::vec3(target));
    if (bind != editor.mesh().position(v)) editor.move_vertex(v, bind);
  }

 private:
  Unposer unpose_;
};

}  // namespace deepcut::drill
