// SPDX-License-Identifier: MIT
#pragma once
// Constrained Delaunay triangulation by Lawson flips, with point insertion. Private to core:
// used by the drill's rim faces and walls. Unlike FaceRefinement (core/src/ops/common/) it
// flips after each insertion to stay Delaunay and takes only points strictly inside a triangle.

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "geometry/predicates.h"

namespace deepcut::geometry {

/// A triangulation of points in the plane with neighbour links: Lawson flips to the constrained
/// Delaunay triangulation (edges with one triangle are the constraints) and point insertion.
/// The triangles are counter-clockwise and index the caller's point list, which insert() extends.
/// One object can be reset() for polygon after polygon: its lists keep their memory.
class FlipTriangulation {
 public:
  FlipTriangulation() = default;
  FlipTriangulation(std::vector<glm::dvec2>& pts, std::vector<LocalTri> tris);

  /// Starts over on `tris` over `pts` (kept by reference until the next reset).
  void reset(std::vector<glm::dvec2>& pts, const std::vector<LocalTri>& tris);

  const std::vector<LocalTri>& triangles() const { return tris_; }

  /// True if the edge a-b is shared by two triangles.
  bool is_interior(std::uint32_t a, std::uint32_t b) const;

  /// Flips every non-constrained edge whose opposite point lies inside the circumcircle (with a
  /// relative tolerance) until none is left.
  void make_delaunay();

  /// Inserts `p` if it lies strictly inside a triangle (appending it to the points).
  bool insert(const glm::dvec2& p);

 private:
  void link_neighbours();
  void relink(int n, int from, int to);
  double orient_rel(std::uint32_t a, std::uint32_t b, const glm::dvec2& p) const;
  int locate(const glm::dvec2& p) const;
  int scan(const glm::dvec2& p) const;
  void legalize();

  std::vector<glm::dvec2>* pts_ = nullptr;
  std::vector<LocalTri> tris_;
  std::vector<std::array<int, 3>> nbr_;
  std::size_t last_ = 0;
  // Scratch kept between calls: the edges still to check (triangle, edge), and the half-edges
  // grouped by their start point (first_out_[p] .. first_out_[p + 1] in out_, triangle order).
  std::vector<std::pair<int, int>> stack_;
  std::vector<std::uint32_t> first_out_;
  std::vector<std::pair<std::uint32_t, int>> out_;  // (end point, triangle)
};

}  // namespace deepcut::geometry
