// SPDX-License-Identifier: MIT
#pragma once
/// @file adjacency.h
/// Vertex->faces, vertex->vertices, face->faces (across edges), boundary / non-manifold / seam
/// edges and connected components. `build` is the slow, obviously correct reference;
/// `apply(log)` updates an existing adjacency from an edit log, touching only what changed.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "deepcut/core/edit_log.h"
#include "deepcut/core/surface_mesh.h"

namespace deepcut {

/// An undirected edge with `a < b`.
struct Edge {
  VertexId a, b;
  bool operator==(const Edge& o) const { return a == o.a && b == o.b; }
  bool operator<(const Edge& o) const { return a == o.a ? b < o.b : a < o.a; }
};
inline Edge make_edge(VertexId u, VertexId v) { return u < v ? Edge{u, v} : Edge{v, u}; }

/// The faces around one vertex, sorted by id: a view into an Adjacency, valid until its next
/// update.
class VertexFaces {
 public:
  VertexFaces(const FaceId* first, std::size_t count) : first_(first), count_(count) {}
  const FaceId* begin() const { return first_; }
  const FaceId* end() const { return first_ + count_; }
  std::size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  const FaceId& front() const { return first_[0]; }
  const FaceId& back() const { return first_[count_ - 1]; }
  const FaceId& operator[](std::size_t i) const { return first_[i]; }

 private:
  const FaceId* first_;
  std::size_t count_;
};

class Adjacency {
 public:
  Adjacency() = default;
  /// A copy keeps every vertex list's spare room (see `reserve`), so the copy's first edit does
  /// not reallocate the lists it touches either.
  Adjacency(const Adjacency& other);
  Adjacency& operator=(const Adjacency& other);
  Adjacency(Adjacency&&) noexcept = default;
  Adjacency& operator=(Adjacency&&) noexcept = default;

  /// Full rebuild from the live faces of `mesh`. O(#faces).
  static Adjacency build(const SurfaceMesh& mesh);
  /// Updates from the edits of one or more operations, in order. O(#edits).
  void apply(const EditLog& log);
  /// Reserves room for `vertices` vertices and `faces` face slots, so updates that grow the
  /// adjacency up to these sizes never move the lists of the vertices `build` saw (call it with
  /// the headroom given to SurfaceMesh::reserve; a copy of an Adjacency keeps only the room it
  /// uses). The added vertices' lists share one pool, which an update may move (a list that
  /// outgrows its room): a VertexFaces view is not held across an update. Also gives
  /// every vertex's face list the few spare entries `build` leaves, so an edit's inserts around
  /// an old vertex do not reallocate its list.
  void reserve(std::size_t vertices, std::size_t faces);

  std::size_t vertex_count() const { return vertex_faces_.size() + added_.size(); }
  /// Live faces around `v`, sorted by id.
  VertexFaces vertex_faces(VertexId v) const {
    if (v.index < vertex_faces_.size())
      return VertexFaces(vertex_faces_[v.index].data(), vertex_faces_[v.index].size());
    const AddedList& list = added_[v.index - vertex_faces_.size()];
    return VertexFaces(added_pool_.data() + list.at, list.size);
  }
  /// Vertices sharing an edge with `v`, sorted by id.
  std::vector<VertexId> vertex_neighbors(VertexId v) const;
  /// Faces sharing an edge with `f`, sorted by id (more than three at non-manifold edges).
  std::vector<FaceId> face_neighbors(FaceId f) const;
  /// Faces using the edge (u, v), sorted; empty if it is not an edge. O(valence).
  std::vector<FaceId> edge_faces(VertexId u, VertexId v) const;
  /// Number of distinct edges of the live faces. O(#faces).
  std::size_t edge_count() const;

  /// Edges with exactly one face, sorted.
  std::vector<Edge> boundary_edges() const;
  /// Edges with three or more faces, sorted.
  std::vector<Edge> nonmanifold_edges() const;
  /// Interior edges whose two faces disagree on any corner attribute at a shared vertex
  /// (UV seams, hard normals), sorted.
  std::vector<Edge> seam_edges(const SurfaceMesh& mesh) const;
  /// Number of vertex-connected components of the live faces.
  std::size_t component_count() const;
  /// Component index per vertex (kInvalidIndex for vertices without faces) and the count.
  std::vector<std::uint32_t> vertex_components(std::size_t* count = nullptr) const;

  /// Same vertices and same faces per vertex (edges follow from those and the faces).
  bool operator==(const Adjacency& other) const;
  bool operator!=(const Adjacency& other) const { return !(*this == other); }

 private:
  // Calls fn(a, b, faces_of_edge) once per edge (a < b) of the live faces.
  template <class Fn>
  void for_each_edge(Fn&& fn) const;
  // Where the list of a vertex an edit made lies in added_pool_: `size` faces from `at`, in room
  // for `room`.
  struct AddedList {
    std::uint32_t at = 0, size = 0, room = 0;
  };
  void add_face(FaceId f, const Triangle& t);
  void remove_face(FaceId f, const Triangle& t);
  void add_vertices(std::size_t count);
  // Moves a full added list to twice its room at added_pool_'s end (its old room is left unused).
  void grow(AddedList& list);

  // Edges are not stored: the faces of edge (u, v) are those in both vertex lists, which are
  // short and sorted. That keeps build and every update to one sorted insert per corner. The
  // vertices `build` saw have a list each; the vertices edits add since share one pool, so a new
  // vertex costs no allocation of its own (a cut adds hundreds).
  std::vector<std::vector<FaceId>> vertex_faces_;
  std::vector<AddedList> added_;
  std::vector<FaceId> added_pool_;
  std::vector<Triangle> face_vertices_;  // by face slot; invalid ids for removed faces
};

}  // namespace deepcut
