// SPDX-License-Identifier: MIT
#pragma once
/// @file skinning.h
/// Animation sampling and linear blend skinning: posed positions and normals for any time.

#include <vector>

#include "deepcut/core/model.h"

namespace deepcut {

/// Local TRS of every node (matrix nodes keep `matrix`, which animation does not touch).
struct Pose {
  std::vector<glm::vec3> translation;
  std::vector<glm::quat> rotation;
  std::vector<glm::vec3> scale;
};

/// The nodes' own TRS: the rest pose.
Pose rest_pose(const Model& model);
/// Rest pose with animation `animation` sampled at `time` (clamped to its key range);
/// `animation < 0` gives the rest pose. Step, linear (slerp for rotations) and cubic spline.
/// @throws Error{InvalidArgument} if `animation` is out of range.
Pose sample_pose(const Model& model, int animation, float time);

/// World matrix of every node for `pose`.
std::vector<glm::mat4> world_matrices(const Model& model, const Pose& pose);

/// Joint matrices of `skin` (world(joint) * inverseBind), one per joint.
std::vector<glm::mat4> joint_matrices(const Model& model, int skin, const std::vector<glm::mat4>& world);

/// World-space positions of the vertices of `mesh`, drawn by node `node` (mesh instance):
/// linear blend skinning when the node has a skin (the node's own transform is ignored, as
/// glTF requires), the node's world matrix otherwise.
std::vector<glm::vec3> posed_positions(const Model& model, int node, const SurfaceMesh& mesh,
                                       const std::vector<glm::mat4>& world);
/// The matrix that takes each vertex of `mesh`, drawn by node `node`, from bind space to world
/// space: the weighted sum of its joint matrices when the node has a skin, the node's world
/// matrix otherwise. One per vertex.
std::vector<glm::mat4> vertex_skin_matrices(const Model& model, int node, const SurfaceMesh& mesh,
                                            const std::vector<glm::mat4>& world);

/// World-space corner normals (one per corner), skinned like the positions and renormalised.
/// Empty if the mesh has no normals.
std::vector<glm::vec3> posed_normals(const Model& model, int node, const SurfaceMesh& mesh,
                                     const std::vector<glm::mat4>& world);

/// Bounding box of every mesh instance in world space for `pose`.
BoundingBox world_bounds(const Model& model, const Pose& pose);

}  // namespace deepcut
