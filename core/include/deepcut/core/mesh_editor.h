// SPDX-License-Identifier: MIT
#pragma once
/// @file mesh_editor.h
/// The only way operations change a mesh's topology. Every call interpolates all attributes
/// (vertex, corner, face) and appends one record to the edit log, so the log cannot drift out of
/// sync with the mesh (geometry-central's MutationManager, kept as data).
///
/// Skin weights of new vertices follow one rule, blend_influences (docs/library.md, "New
/// vertices"). Corner normals are renormalised, tangents keep a unit xyz and the handedness of
/// the dominant source.

#include <array>
#include <utility>
#include <vector>

#include "deepcut/core/edit_log.h"
#include "deepcut/core/surface_mesh.h"

namespace deepcut {

/// Face edits to make in one go (MeshEditor::apply): removals and faces made from parents, kept
/// in the order given. An operation that replaces many faces (a cut's crossed faces) queues them
/// here, so each attribute array blends all the new corners in one call instead of one call per
/// face and array.
class FaceBatch {
 public:
  /// Queues `remove_face(f)`. @pre `f` is a live face before the batch, queued once.
  void remove(FaceId f) { removals_.emplace_back(f, static_cast<std::uint32_t>(faces_.size())); }
  /// Queues `add_face_from(vertices, parent, corner_bary)`.
  void add_from(const Triangle& vertices, FaceId parent, const std::array<glm::vec3, 3>& corner_bary) {
    faces_.push_back(vertices);
    parents_.push_back(parent.index);
    const float w[9] = {corner_bary[0].x, corner_bary[0].y, corner_bary[0].z, corner_bary[1].x, corner_bary[1].y,
                        corner_bary[1].z, corner_bary[2].x, corner_bary[2].y, corner_bary[2].z};
    weights_.insert(weights_.end(), w, w + 9);  // appended as written: no zero fill first
  }
  /// Queues what `add_from(vertices, parent, corner_bary)` and then moving that face would leave:
  /// the face made again from itself (each corner its own, weight 1) onto `vertices`, its corner
  /// normals and tangents normalised a second time. The same attributes as that pair of edits,
  /// without the face in between (a cut's positive side made straight onto the vertex copies).
  void add_moved_from(const Triangle& vertices, FaceId parent, const std::array<glm::vec3, 3>& corner_bary) {
    moved_.push_back(static_cast<std::uint32_t>(faces_.size()));
    add_from(vertices, parent, corner_bary);
  }
  /// Room for `faces` additions and `removals` removals.
  void reserve(std::size_t faces, std::size_t removals);
  bool empty() const { return faces_.empty() && removals_.empty(); }

 private:
  friend class MeshEditor;
  std::vector<Triangle> faces_;
  std::vector<std::uint32_t> parents_;
  std::vector<float> weights_;  // nine per face: corner k's barycentric weights at 3k
  // Each removal, with the number of faces queued before it.
  std::vector<std::pair<FaceId, std::uint32_t>> removals_;
  // The places of the faces add_moved_from queued, ascending.
  std::vector<std::uint32_t> moved_;
};

/// @note The editor looks up the skin, normal and tangent attributes once, when it is made: add
///       such attributes before making the editor (other attributes may come and go).
class MeshEditor {
 public:
  explicit MeshEditor(SurfaceMesh& mesh);

  /// New vertex at parameter `t` on the segment a->b (t = 0 gives a copy of a's attributes).
  /// @throws Error{InvalidArgument} (before any change) for an end that is not a vertex.
  VertexId add_vertex_on_edge(VertexId a, VertexId b, float t);
  /// `add_vertex_on_edge(VertexId(ends[2 * i]), VertexId(ends[2 * i + 1]), t[i])` for i = 0 ..
  /// count - 1 in turn, with the same mesh and log (the attribute arrays grown for many vertices
  /// at once): vertex i is the returned vertex + i. An end may be a vertex made earlier in the
  /// batch. With count 0 nothing changes and the id the next new vertex would get is returned.
  /// @throws Error{InvalidArgument} (before any change) for an end that is not a vertex yet:
  ///         ends 2i and 2i + 1 must be below vertex_count() + i.
  VertexId add_vertices_on_edges(const std::uint32_t* ends, const float* t, std::size_t count);
  /// New vertex at barycentric coordinates `bary` of the triangle (a, b, c).
  /// @throws Error{InvalidArgument} (before any change) for a corner that is not a vertex.
  VertexId add_vertex_in_triangle(const Triangle& tri, const glm::vec3& bary);
  /// Duplicate of `v` (same position and attributes), e.g. one side of a tear.
  VertexId split_vertex(VertexId v);
  /// `split_vertex(VertexId(vertices[i]))` for i = 0 .. count - 1 in turn (each attribute array
  /// written in one call): the copy of vertices[i] is the returned vertex + i.
  /// @throws Error{InvalidArgument} (before any change) for a vertex out of range.
  VertexId split_vertices(const std::uint32_t* vertices, std::size_t count);
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
  /// `add_face(faces[i])` for i = 0 .. count - 1 in turn, with the same mesh and log (each
  /// attribute array grown once for all of them): face i is the returned face + i.
  /// @throws Error{InvalidArgument} (before any change) for a corner that is not a vertex.
  FaceId add_faces(const Triangle* faces, std::size_t count);
  /// Marks `f` deleted. @throws Error{InvalidArgument} if it is already deleted.
  void remove_face(FaceId f);
  /// Makes the queued edits of `batch` and empties it: the same mesh and the same log as its
  /// remove_face and add_face_from calls made one after another, in its order.
  /// @throws Error{InvalidArgument} (before any change) as those calls would, or for a face
  ///         queued for removal twice; the batch then keeps its contents.
  void apply(FaceBatch& batch);

  SurfaceMesh& mesh() { return mesh_; }
  const EditLog& log() const { return log_; }
  /// Room for `edits` more log entries, so an operation that knows its size grows the log once.
  void reserve_log(std::size_t edits) { log_.edits.reserve(log_.edits.size() + edits); }
  EditLog take_log();

 private:
  // `count` new vertices, vertex i the blend of kSources vertices src[kSources * i + k] with
  // weights w[kSources * i + k], logged as VertexAdded. kSources is 1 to kMaxBlendSources (the
  // log entry's slots, the skin blend's room), checked when the call is compiled.
  // @pre every source of vertex i is below vertex_count() + i (the callers check it first).
  template <int kSources>
  VertexId add_blended(const std::uint32_t* src, const float* w, std::size_t count);
  // Corner normals and tangents of the faces [first, first + count) made from `parents` with
  // corner weights `w` (nine per face).
  void fix_corner_directions(FaceId first, std::size_t count, const std::uint32_t* parents, const float* w);
  // The second half of FaceBatch::add_moved_from for the new faces first + moved[i].
  void remake_moved(FaceId first, const std::vector<std::uint32_t>& moved);

  SurfaceMesh& mesh_;
  EditLog log_;
  // Attributes with special interpolation rules, looked up once.
  AttributeArray<glm::u16vec4>* joints_[2] = {nullptr, nullptr};
  AttributeArray<glm::vec4>* weights_[2] = {nullptr, nullptr};
  int skin_sets_ = 0;
  AttributeArray<glm::vec3>* normals_ = nullptr;
  AttributeArray<glm::vec4>* tangents_ = nullptr;
};

/// Most influences a vertex carries: four per JOINTS_n/WEIGHTS_n set, two sets.
inline constexpr int kMaxInfluences = 8;
/// Most sources a new vertex blends (a point in a triangle).
inline constexpr int kMaxBlendSources = 3;

/// The influence rule of every new vertex (cut rims, caps, tear lips, drill rims and walls,
/// refinements), in this one place: a new vertex keeps at most as many influences as its
/// primitive carries (`slots`: 4 with JOINTS_0 only, 8 with JOINTS_1 too). The sources'
/// influences are scaled by the sources' weights and merged by joint, then the largest `slots`
/// are kept, largest first (ties in the order the joints first appear: sources in order, slots
/// in order), renormalised to sum 1; unused slots get joint 0 and weight 0. A vertex whose
/// sources have no weight follows the first source's first joint with weight 1.
/// @param joints, weights  the sources' influences, `slots` per source (source s at s * slots).
/// @param w                the sources' weights (barycentric or edge parameters), `count` of them.
/// @param count            1 to kMaxBlendSources.  @param slots  4 or 8.
/// @param out_joints, out_weights  `slots` results.
/// @throws Error{InvalidArgument} for a count or slots outside those ranges.
void blend_influences(const std::uint16_t* joints, const float* weights, const float* w, int count, int slots,
                      std::uint16_t* out_joints, float* out_weights);

/// One vertex's influences made valid in place: negative or non-finite weights become 0,
/// a joint named twice is merged into its first slot, the weights are renormalised to sum 1
/// (left as they are when they already do, within 2e-7), zero-weight slots get joint 0. The
/// slots keep their order. Used by the editor (after blend_influences), the importer and the
/// exporter.
/// @param joints  `slots` joint indices.  @param weights  `slots` weights (modified in place).
/// @returns false if the weights summed to 0 (or were not finite): then the first slot's joint
///          gets weight 1, so the vertex follows that joint.
bool normalize_influences(std::uint16_t* joints, float* weights, int slots);

/// normalize_influences of influences already checked: every weight finite and >= 0, and no
/// joint named by two slots of positive weight. The same result, without checking again (the
/// importer checks each vertex's influences as it reads them).
bool renormalize_influences(std::uint16_t* joints, float* weights, int slots);

}  // namespace deepcut
