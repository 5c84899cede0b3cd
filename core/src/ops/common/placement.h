// SPDX-License-Identifier: MIT
#pragma once
// Where a vertex an operation makes or moves goes in bind space: the rule the insertions share
// (cut, tear, drill; ops/common/). Private to core.
//
// An operation decides where a new vertex is on the posed surface (where the plane, the swept
// quad or the cylinder crosses it: what the designer saw). MeshEditor blends its skin weights
// and interpolates every attribute; its bind position is then the posed point unposed through
// the vertex's own blended skin (PosedMesh::unpose). Interpolating the bind position instead
// would put it beside the posed point: linear blend skinning is not linear in the blended
// weights. So every new vertex lies on the posed input surface at the operation's pose, and a
// moved vertex moves by exactly the posed displacement the operation chose.

#include <cstddef>
#include <functional>
#include <glm/glm.hpp>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/posed_model.h"

namespace deepcut::detail {

/// Maps the posed position of vertex `v` of `mesh` (its skin weights already set) back to bind
/// space. Empty: posed positions are bind positions.
using Unposer = std::function<glm::vec3(const SurfaceMesh& mesh, VertexId v, const glm::vec3& posed)>;

/// Places the vertices of one edit of one instance.
///
/// Unskinned instances are posed by one affine map (the node's), which maps interpolation to
/// interpolation: the bind position the edit interpolated already poses at the exact point, and
/// is kept. So is it in a skinned instance whose joint matrices are all nearly one matrix (the
/// rest pose of a model bound at rest, where they differ by float noise) wherever it poses within
/// kNoise of the model size of its target: rest-pose edits give the same bytes as plain
/// interpolation. Everywhere else the target is unposed.
class Placement {
 public:
  /// Posed positions are bind positions: nothing to unpose.
  Placement() = default;
  /// Unposes through `posed` (kept by reference: the instance as the operation starts; its joint
  /// matrices are what is inverted) when it skins `mesh`, unless `posed.no_unpose`. O(joints).
  Placement(const PosedMesh& posed, const SurfaceMesh& mesh);

  /// True when bind positions are found by unposing.
  bool unposes() const { return posed_ != nullptr; }

  /// Bind position of vertex `v` of `mesh` (its skin weights set) whose posed position must be
  /// `target`, given `guess`, the bind position the edit made for it (interpolated from its
  /// sources, or moved by its linear map's inverse): `target` unposed, or `guess` where it is
  /// kept (above). O(influences).
  glm::vec3 bind_position(const SurfaceMesh& mesh, VertexId v, const glm::vec3& target,
                          const glm::vec3& guess) const;

  /// Moves vertex `v` (just made by `editor`, its bind position interpolated) so that it poses at
  /// `target` (bind_position with its bind position as the guess).
  void place(MeshEditor& editor, VertexId v, const glm::vec3& target) const;

  /// `place(editor, ids[i], targets[i])` for i = 0 .. n - 1 (`ids` distinct): the bind positions found over
  /// the pool (more than kPlaceGrain of them), then the vertices moved in order. Each bind position reads
  /// only its own vertex's skin, morph offsets and bind position and the posed input, which moving the others
  /// leaves as they are: the same as `place` one after another.
  void place_all(MeshEditor& editor, const VertexId* ids, const glm::vec3* targets, std::size_t n) const;

  /// Vertices a pool chunk of place_all unposes (a skin blend and an inverse each, about 0.3 us
  /// at 4M triangles); as many or fewer are placed on the calling thread.
  static constexpr std::size_t kPlaceGrain = 256;

  /// Joint matrices count as nearly one matrix when they differ by at most this much: relative
  /// to the largest entry of the linear part, and as a fraction of the model size (the posed
  /// bounds' diagonal) for the translation. Float noise at rest is about 1e-6.
  static constexpr double kNearRest = 1e-4;
  /// A kept guess poses at most this far from its target, as a fraction of the model size (ten
  /// times under the 1e-5 the operations promise; float noise at rest is about 1e-7).
  static constexpr double kNoise = 1e-6;

 private:
  // Moves `v`, whose bind position is `guess`, to `bind` when they differ (place's last step).
  static void move_if_changed(MeshEditor& editor, VertexId v, const glm::vec3& guess, const glm::vec3& bind);

  const PosedMesh* posed_ = nullptr;
  double noise_ = 0.0;            // kNoise in world units
  bool near_one_matrix_ = false;  // the joint matrices are nearly one matrix
};

}  // namespace deepcut::detail
