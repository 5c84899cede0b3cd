// SPDX-License-Identifier: MIT
#pragma once
/// @file weld.h
/// "Model optimisation" in the paper: merge vertices that a file duplicated at UV seams or hard
/// normals into one topological vertex. Corner attributes keep the seam, so nothing is lost.

#include <cstddef>

#include "deepcut/core/surface_mesh.h"

namespace deepcut {

struct WeldReport {
  std::size_t merged = 0;      ///< vertices merged into another
  std::size_t kept_apart = 0;  ///< vertices sharing a position with another but not its skin weights
  std::size_t dropped = 0;     ///< vertices no live face used
};

/// Merges vertices whose every vertex attribute (position, joints, weights, ...) is bitwise
/// equal (+0 and -0 count as equal). Vertices are renumbered in order of first use by the faces;
/// unreferenced vertices are dropped; deleted faces are removed. Vertices at one position with
/// different skin weights are never merged (counted in `kept_apart`).
/// @note This rebuilds the mesh wholesale (an import step), so it records no edit log: build
///       `Adjacency` after it. O(#vertices + #faces) expected.
WeldReport weld(SurfaceMesh& mesh);

}  // namespace deepcut
