// SPDX-License-Identifier: MIT
#pragma once
/// @file io/static_mesh.h
/// Static (unrigged) meshes from formats without skins, such as OBJ, PLY, OFF and STL: the
/// readers (format plugins) fill a `StaticMesh` of plain arrays, and `make_static_model` checks
/// it and turns it into a rigged `Model` with a single root joint, so every operation, the
/// clusters and the exporter treat it like any skinned glTF.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "deepcut/core/model.h"

namespace deepcut {

/// A triangle mesh as a reader found it: points, triangles indexing them, and optional per-point
/// attributes (each either empty or one per point). Points may repeat (OBJ splits a vertex at
/// every UV or normal seam) and may be unreferenced; `make_static_model` welds and drops them.
struct StaticMesh {
  std::vector<glm::vec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<glm::vec3> normals;  ///< per point, any length (normalised on import)
  std::vector<glm::vec2> uvs;      ///< per point
  std::vector<glm::vec4> colors;   ///< per point, RGBA in [0, 1]
  /// What the reader repaired or dropped (polygons triangulated, lines skipped, ...), one entry
  /// per kind, messages without the file name; they start `Model::import_problems`.
  std::vector<ImportProblem> problems;
};

/// Builds an unrigged model from `mesh`: node 0 holds the mesh (named `name`) skinned to node 1,
/// the single joint "root" at the origin (identity inverse bind matrix); every vertex has weight
/// 1 on joint 0. Points with equal positions are welded into one vertex, the per-point
/// attributes becoming corner attributes (`attr::kNormal`, `attr::kUv0`, `attr::kColor0`), so
/// seams survive; unreferenced points and triangles that repeat a vertex are dropped, normals
/// are normalised, and attributes with non-finite values are dropped (each listed in
/// `Model::import_problems`).
/// @param file  names the input in messages (the path the user gave).
/// @throws Error{InvalidInput} `"FILE: ..."` when there are no triangles, a position is not
///         finite, an index is past the points, or an attribute array has the wrong length.
Model make_static_model(const StaticMesh& mesh, const std::string& name, const std::string& file);

}  // namespace deepcut
