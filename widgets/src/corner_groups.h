// SPDX-License-Identifier: MIT
#pragma once
// The corners of a mesh's live faces grouped by vertex (a compressed table: each vertex's
// corners lie together, in ascending order). The first build of the view data groups corners
// into points with it: two flat arrays, built with two streaming passes, where the corner lists
// that later steps need (ViewPolyData's doubly linked lists, four arrays per corner) wait until
// the view is idle.

#include <cstdint>
#include <vector>

#include "deepcut/core/surface_mesh.h"

namespace deepcut {

struct CornerGroups {
  /// Vertex v's corners are corner[offset[v]] .. corner[offset[v + 1]] (vertex_count + 1 entries).
  std::vector<std::uint32_t> offset;
  std::vector<std::uint32_t> corner;
  /// Some live face names one vertex three times (its cell may name one point three times).
  bool one_vertex_face = false;
};

/// Groups the corners (3 f + k) of every live face of `mesh` by the vertex they name, over the
/// pool; the same whatever the thread count.
/// @pre every live face names vertices below the mesh's vertex_count.
CornerGroups group_corners(const SurfaceMesh& mesh);

}  // namespace deepcut
