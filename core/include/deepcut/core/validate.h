// SPDX-License-Identifier: MIT
#pragma once
/// @file validate.h
/// Statistics and problem reports for a model (what `deepcut info` prints).

#include <string>
#include <vector>

#include "deepcut/core/model.h"

namespace deepcut {

struct ModelStats {
  std::size_t nodes = 0, meshes = 0, primitives = 0;
  std::size_t gltf_vertices = 0;    ///< glTF vertex count as loaded
  std::size_t welded_vertices = 0;  ///< topological vertices after weld (referenced ones)
  std::size_t triangles = 0;
  std::size_t skins = 0, joints = 0;  ///< joints: distinct joint nodes over all skins
  std::size_t animations = 0, materials = 0, textures = 0, images = 0;
  std::size_t boundary_edges = 0, nonmanifold_edges = 0, seam_edges = 0, components = 0;
  BoundingBox bounds;  ///< rest pose, world space
};

ModelStats compute_stats(const Model& model);

/// Problems of a loaded model, one entry per kind (what `deepcut info` lists): what the importer
/// repaired or dropped (`Model::import_problems`), then the checks of every primitive (weights
/// not normalised, joint index out of range, degenerate and duplicate triangles, non-manifold
/// edges and vertices, normals pointing against the winding, primitives without triangles,
/// non-finite values), each kind summed over the primitives.
/// @note O(faces) per primitive (it builds the adjacency).
std::vector<ImportProblem> model_problems(const Model& model);

/// The messages of `model_problems`, one line each.
std::vector<std::string> find_problems(const Model& model);

/// Checks a mesh's internal consistency (indices in range, attribute sizes, finite positions,
/// weights normalised). @throws Error{InvariantViolated} naming the first violation.
void validate_mesh(const SurfaceMesh& mesh, std::size_t joint_count = 0);

}  // namespace deepcut
