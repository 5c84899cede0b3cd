// SPDX-License-Identifier: MIT
#pragma once
/// @file surface_mesh.h
/// A triangle mesh with named attribute arrays per vertex, per face and per face corner.
/// Connectivity is a list of triangles; derived neighbourhoods live in `Adjacency`.
/// Faces are deleted by marking (ids stay stable through an operation);
/// `compact()` removes them explicitly.

#include <array>
#include <cstdint>
#include <vector>

#include "deepcut/core/attributes.h"
#include "deepcut/core/types.h"

namespace deepcut {

namespace detail {
struct TrustedAssign;
}  // namespace detail

using Triangle = std::array<VertexId, 3>;
class SurfaceMesh;

/// Watches a mesh while an operation edits it in place, so the step can be undone from what it
/// touched (model_undo.h records steps so): told before an existing vertex or face is written,
/// and handed the mesh's content before it is overwritten (assigned, `assign`, `compact`) or
/// destroyed. `id` is what the watcher gave the mesh. Copies of a watched mesh are not watched;
/// a moved mesh takes its watcher along.
class MeshObserver {
 public:
  virtual ~MeshObserver() = default;
  virtual void vertex_writing(std::uint32_t id, const SurfaceMesh& mesh, VertexId v) = 0;
  virtual void face_writing(std::uint32_t id, const SurfaceMesh& mesh, FaceId f) = 0;
  virtual void released(std::uint32_t id, SurfaceMesh&& content) noexcept = 0;
};

/// Elements cut off the end of a mesh (`SurfaceMesh::take_tail`), to be appended again.
struct MeshTail {
  std::vector<Triangle> faces;  ///< still naming the mesh's vertices
  std::vector<std::uint8_t> deleted;
  AttributeSet vertex_attrs, face_attrs, corner_attrs;
  std::size_t bytes() const;
};

class SurfaceMesh {
 public:
  SurfaceMesh();

  // --- sizes -------------------------------------------------------------------------------
  /// Number of vertex slots (vertices are never deleted, only left unreferenced).
  std::size_t vertex_count() const { return vattrs_.size(); }
  /// Number of face slots, deleted ones included.
  std::size_t face_slots() const { return faces_.size(); }
  /// Number of live (not deleted) faces.
  std::size_t face_count() const { return faces_.size() - deleted_count_; }
  bool is_deleted(FaceId f) const { return deleted_[f.index] != 0; }

  // --- construction (importers and generators; operations use MeshEditor) -------------------
  /// Appends a vertex at `p`; every other vertex attribute gets its default value.
  VertexId add_vertex(const glm::vec3& p);
  /// Appends a triangle; corner and face attributes get their default values.
  /// @throws Error{InvalidArgument} if an index is out of range.
  FaceId add_face(VertexId a, VertexId b, VertexId c);
  /// `add_face(faces[i][0], faces[i][1], faces[i][2])` for i = 0 .. count - 1 in turn, each
  /// attribute array grown once for all of them. @returns the first new face.
  /// @throws Error{InvalidArgument} (before any change) if an index is out of range.
  FaceId add_faces(const Triangle* faces, std::size_t count);
  /// Appends a triangle made from face `parent`: its face attributes copy the parent's, and
  /// corner `k`'s attributes blend the parent's three corners with weights `w[3k .. 3k + 2]`.
  /// The same result as `add_face` then `copy`/`set_blend3`, each attribute written once.
  /// @throws Error{InvalidArgument} if an index is out of range.
  FaceId add_face_from(VertexId a, VertexId b, VertexId c, FaceId parent, const float* w);
  /// `add_face_from(faces[i][0], faces[i][1], faces[i][2], FaceId(parents[i]), w + 9 * i)` for
  /// i = 0 .. count - 1 in turn, each attribute array written in one call for all of them.
  /// @returns the first new face. @throws Error{InvalidArgument} (before any change) if an index
  ///          is out of range.
  FaceId add_faces_from(const Triangle* faces, const std::uint32_t* parents, const float* w, std::size_t count);
  /// Reserves room in every array (vertex, face and corner attributes included), so edits that
  /// grow the mesh up to these sizes never reallocate: interactive sessions call it once with
  /// some headroom after loading, which keeps the first operation from paying for the growth.
  void reserve(std::size_t vertices, std::size_t faces);

  // --- access ------------------------------------------------------------------------------
  const Triangle& face(FaceId f) const { return faces_[f.index]; }
  const std::vector<Triangle>& faces() const { return faces_; }
  std::vector<glm::vec3>& positions() { return positions_->data(); }
  const std::vector<glm::vec3>& positions() const { return positions_->data(); }
  const glm::vec3& position(VertexId v) const { return (*positions_)[v.index]; }

  /// Add, get or remove vertex attributes here; never assign a whole AttributeSet to it
  /// (use `assign`), since the positions array must stay the one the mesh knows.
  AttributeSet& vertex_attrs() { return vattrs_; }
  const AttributeSet& vertex_attrs() const { return vattrs_; }
  AttributeSet& face_attrs() { return fattrs_; }
  const AttributeSet& face_attrs() const { return fattrs_; }
  /// Corner `k` of face `f` is element `3 * f + k`.
  AttributeSet& corner_attrs() { return cattrs_; }
  const AttributeSet& corner_attrs() const { return cattrs_; }
  static std::uint32_t corner(FaceId f, int k) { return 3u * f.index + static_cast<std::uint32_t>(k); }

  /// Live faces, in order.
  template <class F>
  void for_each_face(F&& fn) const {
    for (std::uint32_t i = 0; i < faces_.size(); ++i)
      if (!deleted_[i]) fn(FaceId(i), faces_[i]);
  }

  // --- low-level edits: only MeshEditor (which logs them) and builders call these -----------
  void set_face(FaceId f, const Triangle& t) {
    if (observer_) observer_->face_writing(observer_id_, *this, f);
    faces_[f.index] = t;
  }
  void mark_deleted(FaceId f);
  /// Replaces the whole mesh (wholesale builders such as weld). `vertex_attrs` must hold
  /// attr::kPosition; sizes must agree (vertices, faces, 3 x faces). Deleted marks are cleared.
  /// @throws Error{InvalidArgument} on a size mismatch or a face index out of range.
  void assign(std::vector<Triangle> faces, AttributeSet vertex_attrs, AttributeSet face_attrs, AttributeSet corner_attrs);
  /// Drops deleted faces and unreferenced vertices; attributes follow.
  /// @returns the old-to-new vertex map (kInvalidIndex for dropped vertices).
  std::vector<std::uint32_t> compact();

  // --- undo (model_undo.h) --------------------------------------------------------------------
  /// Watches the mesh (nullptr: no more). Code that writes an existing vertex's attributes
  /// other than through MeshEditor calls `writing_vertex` first; face writes here tell it.
  void watch(MeshObserver* observer, std::uint32_t id) {
    observer_ = observer;
    observer_id_ = id;
  }
  MeshObserver* observer() const { return observer_; }
  std::uint32_t observer_id() const { return observer_id_; }
  /// Tells the watcher (if any) that vertex `v`'s attributes are about to be written.
  void writing_vertex(VertexId v) const {
    if (observer_) observer_->vertex_writing(observer_id_, *this, v);
  }
  /// Cuts the vertices from `vertices` on and the face slots from `faces` on off the mesh (the
  /// faces kept must not use the vertices cut) and hands them over; capacity stays.
  MeshTail take_tail(std::size_t vertices, std::size_t faces);
  /// Appends a tail taken by `take_tail` (same attributes). @throws Error{InvalidArgument}
  /// when its attributes differ.
  void append_tail(const MeshTail& tail);
  /// Swaps face `f`'s corners and deleted mark with `corners` and `deleted` (undo records).
  void swap_face(FaceId f, Triangle& corners, std::uint8_t& deleted);
  /// Bytes held by every array, room reserved included.
  std::size_t capacity_bytes() const;

  // --- geometry ----------------------------------------------------------------------------
  BoundingBox bounds() const;
  /// Sum of the areas of live faces (bind positions unless `positions` is given).
  double area(const std::vector<glm::vec3>* positions = nullptr) const;
  /// Signed volume enclosed by live faces (meaningful for closed, consistently oriented meshes).
  double volume(const std::vector<glm::vec3>* positions = nullptr) const;

 private:
  friend struct detail::TrustedAssign;  // private to core: the mesh surgery's pieces
  /// `assign` for arrays the caller built itself and knows to be consistent (a mesh's pieces made
  /// by the mesh surgery): the pass over every face index that `assign` checks is skipped.
  /// @pre `vertex_attrs` holds attr::kPosition, the sizes agree and every face index is in range.
  void assign_trusted(std::vector<Triangle> faces, AttributeSet vertex_attrs, AttributeSet face_attrs,
                      AttributeSet corner_attrs);

  std::vector<Triangle> faces_;
  std::vector<std::uint8_t> deleted_;
  std::size_t deleted_count_ = 0;
  AttributeSet vattrs_, fattrs_, cattrs_;
  AttributeArray<glm::vec3>* positions_ = nullptr;
  MeshObserver* observer_ = nullptr;
  std::uint32_t observer_id_ = 0;
  /// Hands the content to the watcher (the mesh is left empty and unwatched).
  void release();

 public:
  SurfaceMesh(const SurfaceMesh& other);
  SurfaceMesh& operator=(const SurfaceMesh& other);
  SurfaceMesh(SurfaceMesh&& other) noexcept;
  SurfaceMesh& operator=(SurfaceMesh&& other) noexcept;
  ~SurfaceMesh();
};

}  // namespace deepcut
