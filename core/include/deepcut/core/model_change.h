// SPDX-License-Identifier: MIT
#pragma once
/// @file model_change.h
/// What one step (an operation, its undo or its redo) changed in a model, in a form that the
/// things drawn from the model (the studio's scene, its VTK arrays, the posed models) follow in
/// O(change) instead of rebuilding: per edited primitive, the sizes before the step and the
/// existing elements it rewrote. Elements past the old sizes are new (when the mesh grew) or gone
/// (when it shrank, as an undo does); everything not listed is unchanged, byte for byte.

#include <cstddef>
#include <vector>

#include "deepcut/core/types.h"

namespace deepcut {

/// One primitive edited in place (mesh `mesh`, primitive `primitive`, at the same indices before
/// and after the step).
struct PrimitiveChange {
  int mesh = -1, primitive = -1;
  /// Vertex and face slot counts before the step (compare with the mesh's counts now).
  std::size_t vertices_before = 0, faces_before = 0;
  /// Existing vertices (index < min(vertices_before, vertex_count now)) whose position or other
  /// vertex attributes changed, each once, increasing.
  std::vector<VertexId> vertices;
  /// Existing face slots (index < min(faces_before, face_slots now)) whose corners, deleted mark,
  /// corner or face attributes changed, each once, increasing.
  std::vector<FaceId> faces;
};

struct ModelChange {
  /// Anything beyond in-place primitive edits changed: nodes, meshes or primitives were added,
  /// removed or replaced (a cut makes piece nodes; a drill's wall adds a primitive), or the step
  /// cannot say what it changed. Followers rebuild; `primitives` is then not meaningful.
  bool structure = false;
  /// The primitives edited in place (none when nothing changed), in (mesh, primitive) order.
  std::vector<PrimitiveChange> primitives;
  bool empty() const { return !structure && primitives.empty(); }
};

}  // namespace deepcut
