// SPDX-License-Identifier: MIT
#pragma once
/// @file view_poly_data.h
/// The vtkPolyData the studio's view draws one primitive with, laid out by slot so that a step
/// (an operation, its undo or redo, described by a PrimitiveChange) updates it in O(change)
/// instead of converting the whole mesh again:
/// - cell i is face slot i, always a triangle; a deleted face is a degenerate cell (all three
///   ids the same point), which draws nothing and is never picked, so cell ids never shift;
/// - with corner normals or UVs the points are the corners (point 3f + k is corner k of face f:
///   split wherever corners differ, as a renderer needs); without them, one point per vertex
///   slot. Points are appended and truncated with the mesh.
/// Arrays (as `to_poly_data` names them, so picking and colouring read either): point data
/// "vertex_id", "uv0" (texture coordinates, made the active ones; kept up to date by name, so
/// a viewer may unset them while no texture reads them), "normal" (the posed corner normals,
/// else the mesh's); cell data "face_id". (No "corner_id": in the corner layout point i is
/// corner i.) Arrays are filled through their raw storage, in parallel, without per-element
/// virtual calls.

#include <cstdint>
#include <vector>

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include "deepcut/core/model_change.h"
#include "deepcut/core/surface_mesh.h"

namespace deepcut {

class ViewPolyData {
 public:
  /// Converts `mesh` drawn at `positions` (one per vertex slot) with `corner_normals` (one per
  /// corner, e.g. the posed ones; null or empty: the mesh's own normals, if any).
  /// O(vertices + faces), in parallel.
  ViewPolyData(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
               const std::vector<glm::vec3>* corner_normals = nullptr);

  vtkPolyData* poly() const { return poly_; }
  /// True when points are corners (the mesh has corner normals or UVs).
  bool corner_points() const { return corners_; }

  /// Follows one step on the mesh: `mesh`, `positions` and `corner_normals` are the state after
  /// it, `change` what it changed (sizes before it, listed vertices and faces). Rewrites the
  /// listed and new elements (and the corner points of listed vertices), truncates what is gone,
  /// marks what it wrote modified. Colours set on the data are dropped when the point or cell
  /// count changes (the caller colours again). O(change).
  void update(const SurfaceMesh& mesh, const std::vector<glm::vec3>& positions,
              const std::vector<glm::vec3>* corner_normals, const PrimitiveChange& change);

  /// Moves every point to `positions` (one per vertex slot) and, when given and not empty, sets
  /// the normals from `corner_normals` (a new pose). O(points), in parallel.
  void set_positions(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>* corner_normals);

 private:
  struct Writer;
  void resize(const SurfaceMesh& mesh);
  /// Links every corner of a live face to its vertex (the lists of a new mesh), over the pool.
  void link_all(const SurfaceMesh& mesh);
  void link(std::uint32_t c, std::uint32_t v);
  void unlink(std::uint32_t c);
  void modified();

  bool corners_ = false;
  vtkSmartPointer<vtkPolyData> poly_;
  // Corner layout: the corners of each vertex slot, as a doubly linked list through the corners
  // (kInvalidIndex ends it), and the vertex each corner is linked to (kInvalidIndex: a corner
  // of a deleted face, linked to none): moving a vertex rewrites exactly its corners' points.
  std::vector<std::uint32_t> first_, next_, prev_, corner_vertex_;
};

}  // namespace deepcut
