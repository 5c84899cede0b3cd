// SPDX-License-Identifier: MIT
#pragma once
/// @file edit_log.h
/// What a topology change did, as data (CGAL's corefinement visitor, kept as a value). Caches
/// such as `Adjacency` and the soft-body clusters update from the log instead of rebuilding.

#include <array>
#include <variant>
#include <vector>

#include "deepcut/core/surface_mesh.h"

namespace deepcut {

/// A new vertex whose attributes are the blend of up to three sources
/// (`from[i]` invalid when unused): an edge split has two, a point inside a face three.
struct VertexAdded {
  VertexId v;
  std::array<VertexId, 3> from;
  std::array<float, 3> weight;
};
/// A copy of `original` at the same position (tear lips); the copy gets all its attributes.
struct VertexSplit {
  VertexId original, copy;
};
/// A vertex moved; topology unchanged. A new vertex's VertexMoved follows its VertexAdded, not always next.
struct VertexMoved {
  VertexId v;
  glm::vec3 from, to;
};
/// A new face; `parent` is the face it was cut from (invalid for new surface such as caps).
struct FaceAdded {
  FaceId f, parent;
  Triangle vertices;
};
/// A face marked deleted; `vertices` are what it had.
struct FaceRemoved {
  FaceId f;
  Triangle vertices;
};

using Edit = std::variant<VertexAdded, VertexSplit, VertexMoved, FaceAdded, FaceRemoved>;

struct EditLog {
  std::vector<Edit> edits;
  bool empty() const { return edits.empty(); }
  std::size_t size() const { return edits.size(); }
  void append(const EditLog& other) { edits.insert(edits.end(), other.edits.begin(), other.edits.end()); }
};

}  // namespace deepcut
