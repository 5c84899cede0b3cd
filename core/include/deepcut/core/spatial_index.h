// SPDX-License-Identifier: MIT
#pragma once
/// @file spatial_index.h
/// A uniform grid over triangles (their bounding boxes), built once from a set of positions
/// (usually the posed positions the operations test against) and updated from edit logs, so an
/// operation finds the triangles near its tool without scanning the mesh.

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "deepcut/core/edit_log.h"
#include "deepcut/core/surface_mesh.h"

namespace deepcut {

class TriangleGrid {
 public:
  TriangleGrid() = default;

  /// Builds the grid over the live faces of `mesh`, placed at `points`.
  /// @param points     one position per vertex of `mesh` (e.g. posed positions).
  /// @param cell_size  edge length of a cell; 0 (default) picks about two mean triangle extents,
  ///                   limited so the grid has at most about one cell per face.
  /// @throws Error{InvalidArgument} if `points` does not have one entry per vertex.
  /// @note O(faces), in parallel chunks (the layout never depends on the thread count). Faces
  ///       added later outside the build bounds go to the border cells.
  static TriangleGrid build(const SurfaceMesh& mesh, const std::vector<glm::vec3>& points,
                            float cell_size = 0.0f);

  /// Room for `faces` face slots and `vertices` vertex slots in all (as SurfaceMesh::reserve), so
  /// following the first edits files new faces without reallocating the grid's arrays.
  void reserve(std::size_t faces, std::size_t vertices);

  /// Follows an edit log: removed faces leave, added faces join at `points` (which must cover
  /// every vertex the added faces use), and the faces around a moved vertex (VertexMoved: a
  /// drill's snapped vertex, a tear's lips) join the cells of their new place too. `points` holds
  /// the positions after the edits, moved vertices included; the grid remembers where it placed
  /// each vertex, so it finds a moved vertex's faces where they were filed. O(edits).
  void apply(const EditLog& log, const std::vector<glm::vec3>& points);

  /// Follows a mesh cut back to `faces` face slots and `vertices` vertex slots (an undo): the
  /// faces from `faces` on leave, and vertices from `vertices` on are forgotten, so slots made
  /// again later are filed where they are then. O(slots cut).
  void truncate(std::size_t faces, std::size_t vertices);

  /// Live faces in the cells `box` overlaps (a superset of the faces whose bounding box overlaps
  /// it), sorted by id.
  std::vector<FaceId> query_box(const BoundingBox& box) const;
  /// Live faces filed in the cells holding any of `points`, sorted and unique: the union of
  /// `query_box` over each point's own box, visiting each cell once (points along a rim or a
  /// slit share cells).
  std::vector<FaceId> query_points(const std::vector<glm::vec3>& points) const;
  /// Live faces whose bounding box may come within `radius` of the segment a-b (a superset of
  /// the faces meeting the capsule), sorted by id. Visits only the cells along the segment.
  std::vector<FaceId> query_capsule(const glm::vec3& a, const glm::vec3& b, float radius) const;
  /// Live faces in the cells `box` overlaps that also meet the slab of points within
  /// `half_width` of the plane through `point` with normal `normal` (a superset of the faces
  /// whose bounding box overlaps `box` and meets the slab), sorted by id. Visits only the cells
  /// along the plane, so a thin tool (a scalpel's swept quad) costs what its band holds.
  std::vector<FaceId> query_slab(const BoundingBox& box, const glm::vec3& point, const glm::vec3& normal,
                                 float half_width) const;

  /// Bounds of the faces at build time.
  const BoundingBox& bounds() const { return bounds_; }
  float cell_size() const { return cell_; }
  /// Number of live faces indexed.
  std::size_t face_count() const { return live_; }
  bool empty() const { return start_.empty(); }
  /// A hash of the built layout (cells, their face lists, live flags): equal for equal grids.
  /// Tests and the scaling program use it to check that the thread count changes nothing.
  std::uint64_t layout_hash() const;

 private:
  void insert(FaceId f, const Triangle& t, const std::vector<glm::vec3>& points);
  void file(FaceId f, const Triangle& t, const std::vector<glm::vec3>& points);
  glm::ivec3 cell_of(const glm::vec3& p) const;
  std::size_t cell_index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(dims_.y) + static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(dims_.x) +
           static_cast<std::size_t>(x);
  }
  // Calls fn(face) for each live face of cell c: its build-time list, then what `apply` added.
  template <class Fn>
  void for_each_live_in_cell(std::size_t c, Fn&& fn) const;
  void collect_cell(std::size_t c, std::vector<FaceId>& out) const;
  void collect(int x, int y, int z0, int z1, std::vector<FaceId>& out) const;
  static void sort_unique(std::vector<FaceId>& v);

  BoundingBox bounds_;
  glm::vec3 origin_{0.0f};
  float cell_ = 1.0f;
  glm::ivec3 dims_{0};
  // The faces of each cell at build time, packed: cell c holds faces_[start_[c] .. start_[c+1]).
  // One allocation for the whole grid instead of one per cell.
  std::vector<std::uint32_t> start_;
  std::vector<std::uint32_t> faces_;
  // Faces that `apply` added, per cell, made on demand.
  std::unordered_map<std::size_t, std::vector<std::uint32_t>> added_;
  std::vector<std::uint8_t> alive_;  // by face slot
  std::size_t live_ = 0;
  // The corners of every face slot and where each vertex was when its faces were filed: the
  // faces around a moved vertex are those of its old cell that use it.
  std::vector<Triangle> tris_;
  std::vector<glm::vec3> placed_;
};

}  // namespace deepcut
