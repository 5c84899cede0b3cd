// SPDX-License-Identifier: MIT
#pragma once
/// @file skinning.h
/// Animation sampling and linear blend skinning: posed positions and normals for any time.
/// Morph targets (morph.h) are applied to the bind positions and normals before skinning.

#include <cstring>
#include <map>
#include <utility>
#include <vector>

#include "deepcut/core/model.h"

namespace deepcut {

/// Local TRS of every node (matrix nodes keep `matrix`, which animation does not touch).
struct Pose {
  std::vector<glm::vec3> translation;
  std::vector<glm::quat> rotation;
  std::vector<glm::vec3> scale;
  /// Morph weights per node: `node.weights`, else its mesh's `weights`, overridden by animation
  /// channels on `weights` (empty for nodes that draw no morphing mesh).
  std::vector<std::vector<float>> weights;
};

/// Which pose of a model: an animation and a time (`animation` -1: the rest pose), plus morph
/// weights set by hand for some nodes (a designer's expression, from the studio's morph weights
/// panel), which replace what the node's defaults and the animation give those nodes.
struct PoseKey {
  int animation = -1;
  float time = 0.0f;
  /// Node index -> its weights, one per morph target of its mesh: entry i replaces the sampled
  /// weight of target i (a shorter list leaves the later targets as sampled; entries past the
  /// targets and nodes without morph targets are ignored).
  std::map<int, std::vector<float>> weights;

  PoseKey() = default;
  PoseKey(int animation_, float time_, std::map<int, std::vector<float>> weights_ = {})
      : animation(animation_), time(time_), weights(std::move(weights_)) {}
  friend bool operator==(const PoseKey& a, const PoseKey& b) {
    return a.animation == b.animation && a.time == b.time && a.weights == b.weights;
  }
  friend bool operator!=(const PoseKey& a, const PoseKey& b) { return !(a == b); }
};

/// The nodes' own TRS and default morph weights (default_morph_weights): the rest pose.
Pose rest_pose(const Model& model);
/// Rest pose with animation `animation` sampled at `time` (clamped to its key range);
/// `animation < 0` gives the rest pose. Step, linear (slerp for rotations) and cubic spline;
/// channels on `weights` give every target of the node's mesh (N components per key).
/// @throws Error{InvalidArgument} if `animation` is out of range.
Pose sample_pose(const Model& model, int animation, float time);
/// sample_pose(model, key.animation, key.time) with `key.weights` replacing the sampled weights.
/// @throws Error{InvalidArgument} if `key.animation` is out of range.
Pose sample_pose(const Model& model, const PoseKey& key);

/// World matrix of every node for `pose`.
std::vector<glm::mat4> world_matrices(const Model& model, const Pose& pose);

/// Joint matrices of `skin` (world(joint) * inverseBind), one per joint.
std::vector<glm::mat4> joint_matrices(const Model& model, int skin, const std::vector<glm::mat4>& world);

/// Linear blend skinning of one mesh's vertices: its JOINTS_0/WEIGHTS_0 (and _1) looked up once,
/// then the blended matrix of any vertex. The one place the blend is written (posing, the tear's
/// per-vertex frames, the drill's inverse skinning of new wall vertices).
class SkinBlend {
 public:
  /// @param joints  joint matrices of the skin (joint_matrices); kept by reference.
  SkinBlend(const SurfaceMesh& mesh, const std::vector<glm::mat4>& joints)
      : joints_(joints),
        j0_(mesh.vertex_attrs().find<glm::u16vec4>(attr::kJoints0)),
        w0_(mesh.vertex_attrs().find<glm::vec4>(attr::kWeights0)),
        j1_(mesh.vertex_attrs().find<glm::u16vec4>(attr::kJoints1)),
        w1_(mesh.vertex_attrs().find<glm::vec4>(attr::kWeights1)) {
    if (!j1_ || !w1_) j1_ = nullptr, w1_ = nullptr;
  }
  /// False when there is nothing to blend (no joints, or no JOINTS_0/WEIGHTS_0): callers use the
  /// node's world matrix instead.
  bool skinned() const { return !joints_.empty() && j0_ && w0_; }
  /// Sum of the vertex's joint matrices weighted by its weights; zero weights and joints past the
  /// skin are skipped (as glTF viewers do). @pre skinned().
  glm::mat4 matrix(std::size_t v) const {
    glm::mat4 m(0.0f);
    add(m, (*j0_)[v], (*w0_)[v]);
    if (j1_) add(m, (*j1_)[v], (*w1_)[v]);
    return m;
  }
  /// Whether vertices u and v have the same joints and weights, bit for bit (the sets matrix()
  /// reads): then they have one matrix for certain. @pre skinned().
  bool same_influences(std::size_t u, std::size_t v) const {
    return same_set(j0_, w0_, u, v) && (!j1_ || same_set(j1_, w1_, u, v));
  }

 private:
  void add(glm::mat4& m, const glm::u16vec4& j, const glm::vec4& w) const {
    for (int c = 0; c < 4; ++c)
      if (w[c] != 0.0f && j[c] < joints_.size()) m += w[c] * joints_[j[c]];
  }
  static bool same_set(const AttributeArray<glm::u16vec4>* j, const AttributeArray<glm::vec4>* w,
                       std::size_t u, std::size_t v) {
    return std::memcmp(&(*j)[u], &(*j)[v], sizeof(glm::u16vec4)) == 0 &&
           std::memcmp(&(*w)[u], &(*w)[v], sizeof(glm::vec4)) == 0;
  }
  const std::vector<glm::mat4>& joints_;
  const AttributeArray<glm::u16vec4>* j0_;
  const AttributeArray<glm::vec4>* w0_;
  const AttributeArray<glm::u16vec4>* j1_;
  const AttributeArray<glm::vec4>* w1_;
};

/// World-space positions of the vertices of `mesh`, drawn by node `node` (mesh instance), morphed
/// with `weights` (one per target: `Pose::weights[node]`), then linear blend skinning when the node
/// has a skin (the node's own transform is ignored, as glTF requires), the node's world matrix
/// otherwise.
std::vector<glm::vec3> posed_positions(const Model& model, int node, const SurfaceMesh& mesh,
                                       const std::vector<glm::mat4>& world, const std::vector<float>& weights);
/// posed_positions at the node's default morph weights (default_morph_weights: the rest pose's):
/// for a pose whose animation drives weights, pass `Pose::weights[node]` instead.
std::vector<glm::vec3> posed_positions(const Model& model, int node, const SurfaceMesh& mesh,
                                       const std::vector<glm::mat4>& world);
/// The matrix that takes each vertex of `mesh`, drawn by node `node`, from (morphed) bind space
/// to world space: the weighted sum of its joint matrices when the node has a skin, the node's
/// world matrix otherwise. One per vertex. It applies to the morphed bind position
/// (MorphBlend::position), not the stored one, when the pose has morph weights.
std::vector<glm::mat4> vertex_skin_matrices(const Model& model, int node, const SurfaceMesh& mesh,
                                            const std::vector<glm::mat4>& world);

/// World-space corner normals (one per corner), morphed with `weights`, skinned like the
/// positions and renormalised. Empty if the mesh has no normals.
std::vector<glm::vec3> posed_normals(const Model& model, int node, const SurfaceMesh& mesh,
                                     const std::vector<glm::mat4>& world, const std::vector<float>& weights);
/// posed_normals at the node's default morph weights (default_morph_weights).
std::vector<glm::vec3> posed_normals(const Model& model, int node, const SurfaceMesh& mesh,
                                     const std::vector<glm::mat4>& world);

/// Bounding box of every mesh instance in world space for `pose` (its morph weights included).
BoundingBox world_bounds(const Model& model, const Pose& pose);
/// Bounding box of the corners of `mesh`'s live faces at `positions` (one per vertex slot), over
/// the pool: what world_bounds measures of each instance.
BoundingBox face_bounds(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions);

}  // namespace deepcut
