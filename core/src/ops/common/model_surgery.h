// SPDX-License-Identifier: MIT
#pragma once
// Model surgery: the one instance loop of the model-level operations (cut_model, tear_model,
// drill_model) and the edits they make to the scene: copy-on-write of meshes several nodes draw,
// primitives added and removed, piece nodes added, instances dropped, with the PosedModel kept in
// step. Private to core. The data flow is described in docs/architecture.md.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "deepcut/core/model.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/posed_model.h"

namespace deepcut::detail {

/// Core's access to CutResult's vertex sides (the cut writes them, the surgery splits by them).
struct CutSides {
  static std::vector<std::int8_t>& of(CutResult& result) { return result.vertex_sides_; }
  static const std::vector<std::int8_t>& of(const CutResult& result) { return result.vertex_sides_; }
};

/// Core's access to SurfaceMesh::assign_trusted (the surgery's pieces: arrays it built itself).
struct TrustedAssign {
  static void assign(SurfaceMesh& mesh, std::vector<Triangle> faces, AttributeSet vertex_attrs, AttributeSet face_attrs,
                     AttributeSet corner_attrs) {
    mesh.assign_trusted(std::move(faces), std::move(vertex_attrs), std::move(face_attrs), std::move(corner_attrs));
  }
  /// The mesh's triangles, to take apart in place (the mesh is assigned anew right after).
  static std::vector<Triangle>& faces(SurfaceMesh& mesh) { return mesh.faces_; }
  /// The mesh's deleted marks (a piece compacted in place hands their pages past its room back).
  static std::vector<std::uint8_t>& deleted(SurfaceMesh& mesh) { return mesh.deleted_; }
};

/// A copy of `mesh` holding only `faces` (unused vertices dropped, attributes following).
SurfaceMesh extract(const SurfaceMesh& mesh, const std::vector<FaceId>& faces);

/// `extract(mesh, lists[i])` for every list, bit for bit. When no vertex is used by two lists (a
/// cut's sides, its components) every element is copied once, straight into its piece, in one
/// parallel pass: vertices and faces numbered by a running count per list, no sorting, no search.
/// Lists that share vertices are extracted one by one (in parallel).
std::vector<SurfaceMesh> extract_disjoint(const SurfaceMesh& mesh, const std::vector<std::vector<FaceId>>& lists);

/// `extract_disjoint(mesh, lists)`, taking `mesh` apart (it is left empty when the lists use
/// disjoint vertices, as it was otherwise): one piece keeps the mesh's arrays, compacted in place
/// once the other pieces are copied out, so no memory is allocated for it (its arrays keep the
/// mesh's capacity; their pages past the piece's room, split_room, go back to the system, see
/// compact_piece). That piece is the one
/// that saves the most copying: the largest, unless a smaller one has more of its elements where
/// they already are (a leading run of the mesh's vertices and faces, as a cut of a mesh stored in
/// spatial order leaves its lower side). The pieces copied out are written once into new memory,
/// one task per array (largest first); the compaction runs in chunks over every array at once. A
/// watched mesh (SurfaceMesh::watch) is taken apart so only when its watcher is a SplitWatcher that
/// agrees; otherwise it is left whole, every piece copied out of it.
std::vector<SurfaceMesh> split_disjoint(SurfaceMesh&& mesh, const std::vector<std::vector<FaceId>>& lists);

/// A mesh's watcher (MeshObserver) that follows it through split_disjoint instead of being handed
/// it whole: an undo record (model_undo.h) keeps what the pieces do not hold, so a watched mesh is
/// taken apart in place like an unwatched one (the piece that keeps the arrays not copied) and put back
/// together from the pieces on undo. Found by a dynamic_cast on the mesh's observer.
class SplitWatcher {
 public:
  virtual ~SplitWatcher() = default;
  /// True when `mesh`, watched as `id`, may be taken apart (no side effect); false: it is left
  /// whole and stays watched, every piece copied out of it.
  virtual bool accepts(std::uint32_t id, const SurfaceMesh& mesh) const = 0;
  /// `mesh`, accepted, is about to be compacted in place into piece `big` (the others are copied
  /// out): piece k holds its (increasing) vertices `vertices[k]` and faces `faces[k]`. The
  /// watcher keeps what it needs and no longer watches `mesh`; should it throw, it leaves `mesh`
  /// watched as before (the split then fails with the mesh whole). It makes every allocation
  /// `split` needs: `split` does not throw.
  virtual void splitting(std::uint32_t id, SurfaceMesh& mesh, const std::vector<std::vector<std::uint32_t>>& vertices,
                         const std::vector<std::vector<std::uint32_t>>& faces, std::size_t big) = 0;
  /// The pieces made (in the lists' order).
  virtual void split(std::uint32_t id, std::vector<SurfaceMesh>& pieces) = 0;
  /// Memory an accepted split's pieces copied out may take instead of new memory (what steps
  /// being dropped held): an empty array of `like`'s type with room for `elements` and at most
  /// `most` (take_smallest_fit), or nullptr; triangles likewise (empty: none). Asked before
  /// `splitting`, from one thread; what is taken is written over.
  virtual std::unique_ptr<AttributeArrayBase> spare_array(const AttributeArrayBase& like,
                                                          std::size_t elements, std::size_t most) = 0;
  virtual std::vector<Triangle> spare_triangles(std::size_t count, std::size_t most) = 0;
};

/// What a piece split out of a mesh holds of it: piece vertex (face) i is the mesh's vertex (face
/// slot) `vertices[i]` (`faces[i]`), both increasing.
struct PieceElements {
  std::vector<std::uint32_t> vertices, faces;
};

/// The side of each of a cut's pieces and of each vertex (CutResult::piece_sides, vertex_sides).
struct PieceSides {
  const std::vector<int>* list_sides = nullptr;             ///< +1 or -1 per list, each side once
  const std::vector<std::int8_t>* vertex_sides = nullptr;  ///< per vertex; a side no list has: none
};

/// `split_disjoint(mesh, lists)` for lists that are a cut's pieces by side: list `i` holds every
/// live face of side `(*sides.list_sides)[i]` and the faces using vertex `v` lie on side
/// `(*sides.vertex_sides)[v]`, so each vertex's piece is read there instead of marked by a pass
/// over the lists' faces (sides of the wrong sizes: `split_disjoint(mesh, lists)`).
/// `elements` (when not null) gets what each piece holds of `mesh` (left empty when the lists
/// share vertices).
std::vector<SurfaceMesh> split_disjoint(SurfaceMesh&& mesh, const std::vector<std::vector<FaceId>>& lists,
                                        const PieceSides& sides, std::vector<PieceElements>* elements = nullptr);

/// Index of the model's "Cut surface" material (cut caps, drill walls), added on first use.
int cut_surface_material(Model& model);

/// A node name not used yet: `wanted`, or `wanted_2`, `wanted_3`, ...
std::string unique_node_name(const Model& model, const std::string& wanted);

class ModelSurgery;

/// One node drawing a mesh, as the instance loop hands it to the operation.
class InstanceEdit {
 public:
  int node() const { return node_; }
  /// The mesh the node drew when the loop reached it.
  int mesh() const { return mesh_; }
  /// True when other nodes draw that mesh too.
  bool shared() const;
  /// That mesh, to read.
  const Mesh& source() const;
  /// The node's mesh, to edit in place: the model's own when no other node draws it, else a copy
  /// (made on the first call) that becomes this node's own mesh when the callback returns true.
  Mesh& edit();
  /// Instance (node, primitive) of the posed model, or nullptr.
  PosedMesh* posed(int primitive);
  PosedModel& posed_model();
  Model& model();

  /// Removes primitive `primitive` of edit(); the posed model follows (later primitives move down
  /// one).
  void erase_primitive(int primitive);
  /// Appends `primitive` to edit(); the posed model indexes it at that index once the callback
  /// returns true (so erase before adding, as the drill erases swallowed primitives before adding
  /// its walls).
  void add_primitive(Primitive primitive);
  /// The node draws nothing any more: no mesh, no skin, no morph weights or weight channels, no
  /// posed instances (its mesh is emptied when no other node draws it); the callback's edits to a
  /// shared mesh's copy are dropped. Used when an operation leaves the node's mesh without
  /// primitives.
  void drop();
  /// The node draws `mesh` instead (in place of its old mesh when no other node draws that). Its
  /// posed instances are dropped: the next PosedModel::prepare indexes the new mesh. `mesh`
  /// keeps the source's morph weights and target names when it names none.
  void replace_mesh(Mesh mesh);
  /// A new node beside this one (same parent, transform, skin and morph weights; no children, no
  /// camera) named unique_node_name(`name`), drawing `mesh` (appended to the model; it keeps the
  /// source's morph weights and target names when it names none). Every animation channel on
  /// this node's morph weights also drives the new node's, and the posed model gives it this
  /// node's weights set by hand. Returns its index. Adding nodes makes the next
  /// PosedModel::prepare rebuild.
  int add_piece_node(Mesh mesh, const std::string& name);

 private:
  friend class ModelSurgery;
  InstanceEdit(ModelSurgery& surgery, int node, int mesh) : surgery_(surgery), node_(node), mesh_(mesh) {}
  ModelSurgery& surgery_;
  int node_, mesh_;
  bool copied_ = false, dropped_ = false, replaced_ = false;
  Mesh copy_;
  std::vector<int> added_primitives_;
};

/// The instance loop over a model and its posed model.
class ModelSurgery {
 public:
  /// @pre `posed` was prepared for `model` at the operation's pose (PosedModel::prepare).
  ModelSurgery(Model& model, PosedModel& posed);

  /// Calls `fn` for every node drawing a mesh, in node order (nodes it adds are not visited).
  /// `fn` returns true when it edited the instance through edit(): a shared mesh's copy then
  /// becomes the node's own mesh (the posed model renamed), and primitives it added are indexed.
  void for_each_instance(const std::function<bool(InstanceEdit&)>& fn);

  /// Node `node` draws nothing any more (as InstanceEdit::drop, outside the loop).
  void drop_instance(int node);
  /// Number of nodes drawing mesh `mesh` now.
  int users(int mesh) const { return users_[static_cast<std::size_t>(mesh)]; }

  Model& model() { return model_; }
  PosedModel& posed() { return posed_; }

 private:
  friend class InstanceEdit;
  void finish(InstanceEdit& edit);
  Model& model_;
  PosedModel& posed_;
  std::vector<int> users_;    // nodes drawing each mesh
  std::vector<int> parents_;  // of the nodes as the surgery began
};

/// ModelSurgery(model, posed).for_each_instance(fn).
void for_each_instance(Model& model, PosedModel& posed, const std::function<bool(InstanceEdit&)>& fn);

}  // namespace deepcut::detail
