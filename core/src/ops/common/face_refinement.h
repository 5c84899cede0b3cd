// SPDX-License-Identifier: MIT
#pragma once
// Face refinement along inserted points: one mesh triangle split at points given by their
// barycentric coordinates in it, one at a time. Private to core, part of the insertion layer the
// operations share (ops/common/); the tear re-triangulates each face its slit crosses with it.
// Unlike geometry::FlipTriangulation::insert it never flips (the slit's chord must stay the edges
// its points were inserted along) and it takes points on edges and corners.

#include <array>
#include <vector>

#include <glm/glm.hpp>

#include "deepcut/core/surface_mesh.h"

namespace deepcut::detail {

/// Triangulates one face with points inserted in order: each point lands inside a sub-triangle
/// (split in three) or on a sub-edge (the sub-triangles on both sides split in two); a point
/// within 1e-9 (barycentric) of a sub-triangle's corner is that corner. Inserted in order along a
/// straight chord of the face, consecutive chord points always end up joined by an edge.
class FaceRefinement {
 public:
  struct Point {
    VertexId v;
    glm::dvec3 bary;  ///< barycentric coordinates in the face
  };

  /// Starts from the face itself: points 0, 1, 2 are its corners, one triangle {0, 1, 2}.
  explicit FaceRefinement(const Triangle& face);

  /// Inserts vertex `v` at barycentric coordinates `bary` of the face; returns the vertex that
  /// represents it (`v`, or the existing point it coincides with, which is then not added).
  VertexId insert(VertexId v, const glm::dvec3& bary);

  /// Every point: the face's corners, then the inserted ones in order.
  const std::vector<Point>& points() const { return points_; }
  /// The sub-triangles as indices into points(), with the face's orientation.
  const std::vector<std::array<int, 3>>& triangles() const { return tris_; }

 private:
  glm::dvec3 local_bary(const std::array<int, 3>& t, const glm::dvec2& q) const;

  std::vector<Point> points_;
  std::vector<std::array<int, 3>> tris_;
};

}  // namespace deepcut::detail
