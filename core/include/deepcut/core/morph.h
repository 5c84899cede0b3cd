// SPDX-License-Identifier: MIT
#pragma once
/// @file morph.h
/// Morph targets applied to a mesh: the one place the glTF rule is written. The morphed bind
/// position of a vertex is its position plus the sum over targets of weight x POSITION delta
/// (attr::morph_position_name); a corner normal likewise adds weight x NORMAL delta
/// (attr::morph_normal_name) and is renormalised after skinning. Morphing comes before skinning.
/// Posing (skinning.h, posed_model.h), unposing new vertices (PosedMesh::unpose) and the scene's
/// normals all go through `MorphBlend`, so a vertex posed and unposed with the same weights comes
/// back where it was.

#include <cstddef>
#include <vector>

#include "deepcut/core/model.h"

namespace deepcut {

/// Number of morph targets `mesh` carries: how many of attr::morph_position_name(0), (1), ...
/// exist in a row.
int morph_target_count(const SurfaceMesh& mesh);

/// Default morph weights of node `node`: its `weights` when it has one per target of its mesh,
/// else the mesh's `weights` (empty when the node draws no morphing mesh).
std::vector<float> default_morph_weights(const Model& model, int node);

/// The targets of one mesh at given weights: delta arrays looked up once, zero weights and
/// weights past the mesh's targets skipped. Cheap to make; hold it only while the mesh's vertex
/// and corner counts do not change (it keeps pointers to the attribute arrays, which survive
/// growth, so an operation may keep one while adding vertices).
class MorphBlend {
 public:
  MorphBlend() = default;
  /// @param weights  one per target (extra weights are ignored, missing ones count as 0).
  MorphBlend(const SurfaceMesh& mesh, const std::vector<float>& weights);

  /// False when no target moves anything (no targets, or every weight 0).
  bool active() const { return !targets_.empty(); }
  /// Sum of weight x position delta of vertex `v` (zero when inactive).
  glm::vec3 offset(std::size_t v) const {
    glm::vec3 d(0.0f);
    for (const Target& t : targets_) d += t.weight * (*t.position)[v];
    return d;
  }
  /// Morphed bind position of vertex `v` whose stored position is `p`: p + offset(v).
  glm::vec3 position(std::size_t v, const glm::vec3& p) const { return targets_.empty() ? p : p + offset(v); }
  /// Morphed normal of corner `c` whose stored normal is `n` (not renormalised: skinning follows).
  glm::vec3 normal(std::size_t c, const glm::vec3& n) const {
    glm::vec3 out = n;
    for (const Target& t : targets_)
      if (t.normal) out += t.weight * (*t.normal)[c];
    return out;
  }

 private:
  struct Target {
    float weight;
    const AttributeArray<glm::vec3>* position;
    const AttributeArray<glm::vec3>* normal;  // nullptr when the target has no normal deltas
  };
  std::vector<Target> targets_;
};

/// Every per-corner delta array of `mesh` (NORMAL and TANGENT deltas of every target): what a new
/// face without a parent (a cut's cap, a drill's wall) sets to zero at its corners, so its flat or
/// tube normals stay its own whatever the weights (its vertices' POSITION deltas, blended from the
/// rims like their skin weights, keep it attached to the rims).
std::vector<AttributeArray<glm::vec3>*> corner_morph_deltas(SurfaceMesh& mesh);

/// Morphed bind positions of every vertex slot of `mesh` at `weights` (its positions when no
/// target is active).
std::vector<glm::vec3> morphed_positions(const SurfaceMesh& mesh, const std::vector<float>& weights);

}  // namespace deepcut
