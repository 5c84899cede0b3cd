// SPDX-License-Identifier: MIT
#pragma once
/// @file mesh_editor.h
/// The only way operations change a mesh's topology. Every call interpolates all attributes
/// (vertex, corner, face) and appends one record to the edit log, so the log cannot drift out of
/// sync with the mesh (geometry-central's MutationManager, kept as data).
///
/// Skin weights of new vertices follow one rule (docs/library.md, "New vertices"): the union of
/// the sources' joints, the weights interpolated, the largest four per set kept (eight with
/// JOINTS_1/WEIGHTS_1), renormalised to sum 1, unused slots joint 0 with weight 0. Corner
/// normals are renormalised, tangents keep a unit xyz and the handedness of the dominant source.

#include <array>

#include "deepcut/core/edit_log.h"
#include "deepcut/core/surface_mesh.h"

namespace deepcut {

/// @note The editor looks up the skin, normal and tangent attributes once, when it is made: add
///       such attributes before making the editor (other attributes may come and go).
class MeshEditor {
 public:
  explicit MeshEditor(SurfaceMesh& mesh);

  /// New vertex at parameter `t` on the segment a->b (t = 0 gives a copy of a's attributes).
  VertexId add_vertex_on_edge(VertexId a, VertexId b, float t);
  /// New vertex at barycentric coordinates `bary` of the triangle (a, b, c).
  VertexId add_vertex_in_triangle(const Triangle& tri, const glm::vec3& bary);
  /// Duplicate of `v` (same position and attributes), e.g. one side of a tear.
  VertexId split_vertex(VertexId v);
  /// Moves `v` to `p` (bind space).
  void move_vertex(VertexId v, const glm::vec3& p);

  /// New face (a, b, c) cut from `parent`: corner `k`'s attributes are interpolated from the
  /// parent's three corners with barycentric coordinates `corner_bary[k]` (relative to the
  /// parent's corner order); face attributes are copied from the parent.
  /// @pre parent is a valid face slot (deleted or not: its attributes are still stored).
  FaceId add_face_from(const Triangle& vertices, FaceId parent, const std::array<glm::vec3, 3>& corner_bary);
  /// New face with no parent (cap, wall): corner and face attributes get default values;
  /// set them through `mesh().corner_attrs()` afterwards.
  FaceId add_face(const Triangle& vertices);
  /// Marks `f` deleted. @throws Error{InvalidArgument} if it is already deleted.
  void remove_face(FaceId f);

  SurfaceMesh& mesh() { return mesh_; }
  const EditLog& log() const { return log_; }
  EditLog take_log();

 private:
  void fix_skin_weights(VertexId v, const VertexId* src, const float* w, int count);
  void fix_corner_directions(FaceId f, int k, FaceId parent, const std::array<float, 3>& w);

  SurfaceMesh& mesh_;
  EditLog log_;
  // Attributes with special interpolation rules, looked up once.
  AttributeArray<glm::u16vec4>* joints_[2] = {nullptr, nullptr};
  AttributeArray<glm::vec4>* weights_[2] = {nullptr, nullptr};
  int skin_sets_ = 0;
  AttributeArray<glm::vec3>* normals_ = nullptr;
  AttributeArray<glm::vec4>* tangents_ = nullptr;
};

/// Applies the skin-weight rule to one vertex's raw influences: keeps the `slots` largest,
/// renormalises to sum 1, zero-weight slots get joint 0. Used by the editor and the importer.
/// @param joints  `slots` joint indices.  @param weights  `slots` weights (modified in place).
/// @returns false if the weights summed to 0 (or were not finite): then the first slot's joint
///          gets weight 1, so the vertex follows that joint.
bool normalize_influences(std::uint16_t* joints, float* weights, int slots);

}  // namespace deepcut
