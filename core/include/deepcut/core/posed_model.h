// SPDX-License-Identifier: MIT
#pragma once
/// @file posed_model.h
/// The model at one pose. For every mesh instance (node x primitive) of a model posed at one
/// animation time (a `PoseKey`: animation, time and morph weights set by hand; morph targets are
/// applied before skinning, morph.h): the posed world position and the bind-to-world linear map of every vertex,
/// the exact bounds of those positions, and a `TriangleGrid` over the faces at them. Built once
/// per model state and pose (when the studio loads or poses the model, in the CLI before the
/// operation), handed to the operations, and updated from each operation's edit log, so an
/// operation costs what the tool touches, not the mesh. The updated posed model equals a fresh
/// build on the edited model (positions and bounds bit for bit, grids answering every query with
/// the same faces).

#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "deepcut/core/edit_log.h"
#include "deepcut/core/model.h"
#include "deepcut/core/model_change.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/spatial_index.h"
#include "deepcut/core/uninit_vector.h"

namespace deepcut {

/// Gives every primitive of `model` room to grow by about an eighth (SurfaceMesh::reserve), as a
/// session does once after loading: the first operations then edit without reallocating whole
/// attribute arrays, and copies of the model (undo snapshots) keep the room. O(mesh), once.
void reserve_for_operations(Model& model);

/// Everything of a PosedMesh but its per-vertex arrays and its grid: which instance it is and
/// the pose it is posed at. What a copy without grid (PosedModel::positions_copy) copies as it is.
struct PosedMeshHeader {
  int node = -1, mesh = -1, primitive = -1;
  /// Bounds of every entry of `posed` (unreferenced vertices included): the model size the
  /// operations' tolerances are relative to.
  BoundingBox bounds;
  /// The node's world matrix and its skin's joint matrices at the pose (empty when not skinned):
  /// what `unpose` inverts, and how `follow` poses added and moved vertices as a fresh build would.
  glm::mat4 world{1.0f};
  std::vector<glm::mat4> joints;
  /// The node's morph weights at the pose (`Pose::weights[node]`: one per target, empty when its
  /// mesh has none): posing adds their deltas to the bind positions before skinning, `unpose`
  /// subtracts them.
  std::vector<float> weights;
  /// True for a mesh posed at given positions without a pose to invert (`at_positions`): the
  /// operations then leave new vertices at their interpolated bind positions.
  bool no_unpose = false;
  /// True for a mesh posed without a grid (PoseDetail::Positions): `grid` is empty, and
  /// `PosedModel::prepare` builds the instance again before an operation uses it.
  bool gridless = false;
};

/// One drawn primitive: primitive `primitive` of mesh `mesh`, instanced by node `node`.
struct PosedMesh : PosedMeshHeader {
  /// World position of every vertex slot of the primitive's mesh at the index's pose.
  std::vector<glm::vec3> posed;
  /// Linear part of each vertex's bind-to-world map (the weighted sum of its joint matrices
  /// when skinned, else the node's world matrix): `tear_mesh` maps its world moves to bind space
  /// through its inverse. An UninitVector (growing it leaves the new maps unwritten): the
  /// posing loops that size it write every map over the pool, with no serial fill first.
  UninitVector<glm::mat3> linear;
  /// Grid over the live faces at `posed`.
  TriangleGrid grid;

  /// Bind position of vertex `v` of `surface` (skin weights and morph deltas already set, as
  /// MeshEditor sets them for new vertices) whose posed position is `p`: its blended skinning (or
  /// the world matrix) inverted in double precision, minus its own morph offset at `weights`
  /// (M(v)^-1 p - sum_i w_i delta_i(v)), so posing it again gives `p`; `p` itself where the
  /// inverse is not finite.
  glm::vec3 unpose(const SurfaceMesh& surface, VertexId v, const glm::vec3& p) const;

  /// World corner normals of `surface` (the mesh this poses) at this pose: each corner's normal
  /// plus its morph normal deltas at `weights`, through the inverse transpose of its vertex's
  /// `linear` map (the identity when `linear` is empty), renormalised. Empty without normals.
  /// Its capacity is operation_corner_room(face slots) (operation_room.h): the pages past the
  /// corners are not touched, and the array holds the faces later operations add.
  std::vector<glm::vec3> corner_normals(const SurfaceMesh& surface) const;
  /// The same for `surface` made out of a source mesh as `origin` says (this posed mesh derived
  /// from the source's as PosedModel does, ModelChange::origins): the corners of faces with a
  /// source face are copied from `source_normals` (this pose's corner normals of the source),
  /// the others computed. Equal to corner_normals(surface). O(faces) copies, O(rim) computed.
  std::vector<glm::vec3> corner_normals(const SurfaceMesh& surface, const PrimitiveOrigin& origin,
                                        const std::vector<glm::vec3>& source_normals) const;
  /// The same written into `out`, resized to one per corner: every value is written (the mesh
  /// has one corner normal per corner of each face slot), so the array of a mesh dropped
  /// meanwhile may be given to reuse its memory: where its size already holds the corners, no
  /// new pages and no value fill before the copy; where only its capacity does, the part past
  /// its old size is value-filled first, on the calling thread. A new array gets the piece's own
  /// room, piece_corner_room (operation_room.h; as PosedModel gives a piece's positions).
  /// @pre `out` is not `source_normals`.
  void corner_normals(const SurfaceMesh& surface, const PrimitiveOrigin& origin,
                      const std::vector<glm::vec3>& source_normals, std::vector<glm::vec3>& out) const;
  /// Brings `normals` (this pose's `corner_normals` of `surface` before a step) up to date after
  /// the step `change` (PrimitiveChange of this mesh, this posed mesh already following it): one
  /// per corner of every face slot now, recomputed by the same kernel for new faces, listed faces
  /// and the faces around `relinked` (vertices whose linear map the step changed).
  /// Untouched corners are kept. O(change), plus one pass over the faces when `relinked` is not
  /// empty. Leaves `normals` empty when the mesh has no normals.
  void follow_corner_normals(const SurfaceMesh& surface, const PrimitiveChange& change,
                             const std::vector<VertexId>& relinked, std::vector<glm::vec3>& normals) const;

  /// `surface` posed at `posed` (its own positions, i.e. at rest, when empty; one per vertex
  /// otherwise), with bounds and grid, `linear` empty (the identity for every vertex) and no
  /// unposing: a mesh an operation edits where it is drawn. O(vertices + faces).
  /// @throws Error{InvalidArgument} when `posed` is not empty and not one per vertex.
  static PosedMesh at_positions(const SurfaceMesh& surface, std::vector<glm::vec3> posed = {});

  /// Follows `log`, made on `surface` (the mesh this poses): positions (and linear maps, unless
  /// `linear` is empty) of added, split and moved vertices, the bounds, and the grid (removed
  /// faces leave, added faces join, faces around moved vertices are filed again). O(edits).
  void follow(const SurfaceMesh& surface, const EditLog& log);
};

/// Posed instances a follower keeps of contents that left the model in a structural step, by
/// (content tag, node) (ModelChange::left): taken back when an undo or redo brings them back.
using PoseStash = std::map<std::pair<std::uint64_t, int>, PosedMesh>;

/// How much of each PosedMesh a build makes.
enum class PoseDetail {
  Full,       ///< positions, linear maps, bounds and grids: what the operations use
  Positions,  ///< positions, linear maps and bounds, no grids (`PosedMesh::gridless`): what
              ///< drawing a pose uses, cheap enough for every frame of a playback
};

/// The posed model's pose is a `PoseKey` (skinning.h): an animation, a time and morph weights set
/// by hand per node. A front end that lets a designer set an expression (the studio's morph
/// weights panel) builds, reposes and prepares with the key; the (animation, time) forms are the
/// key without weights set by hand, except `prepare`, which the operations call with their
/// recorded animation and time: it keeps the weights set by hand, so an operation is made at the
/// expression shown.
class PosedModel {
 public:
  PosedModel() = default;

  /// Indexes every mesh instance of `model` posed at `key` (animation -1: rest pose; morph
  /// weights sampled, then those set by hand). O(vertices + faces), in parallel (O(vertices) for
  /// PoseDetail::Positions).
  /// @throws Error{InvalidArgument} for an animation index out of range.
  static PosedModel build(const Model& model, const PoseKey& key, PoseDetail detail = PoseDetail::Full);
  /// build(model, PoseKey(animation, time), detail): no weights set by hand.
  static PosedModel build(const Model& model, int animation, float time,
                          PoseDetail detail = PoseDetail::Full);

  /// Poses the same instances of `model` at `key` with PoseDetail::Positions, reusing their
  /// arrays: positions, linear maps and bounds equal a fresh build's bit for bit; grids are
  /// dropped (`prepare` builds them again when an operation needs them). Builds from scratch when
  /// `model` no longer has the indexed instances. O(vertices), in parallel.
  /// @throws Error{InvalidArgument} for an animation index out of range.
  void repose(const Model& model, const PoseKey& key);
  /// repose(model, PoseKey(animation, time)): no weights set by hand.
  void repose(const Model& model, int animation, float time);

  /// A copy without grids (every instance `gridless`, as a PoseDetail::Positions build makes
  /// it), its arrays with the room a build gives them: a front end that keeps such a posed model
  /// of the model it draws up to date (the studio's scene) lends it to an operation that needs no
  /// grid (a cut) instead of posing the model again. O(vertices), copies only.
  PosedModel positions_copy() const;

  /// Every node's world matrix at the pose (empty before a build).
  const std::vector<glm::mat4>& world() const { return world_; }
  /// Node `node`'s morph weights at the pose (`Pose::weights`: defaults, then the animation, then
  /// the weights set by hand; empty for a node without morph targets or out of range).
  const std::vector<float>& weights(int node) const;

  /// True once built (and not invalidated).
  bool valid() const { return valid_; }
  /// True when built for exactly this pose, weights set by hand included.
  bool matches(const PoseKey& key) const { return valid_ && key == key_; }
  /// True when built for this animation and time (`animation` -1 and an out-of-range time both as
  /// given), whatever weights were set by hand.
  bool matches(int animation, float time) const {
    return valid_ && animation == key_.animation && time == key_.time;
  }
  /// The pose: animation, time and the weights set by hand.
  const PoseKey& key() const { return key_; }
  int animation() const { return key_.animation; }
  float time() const { return key_.time; }
  /// Forgets everything (the next `prepare` rebuilds).
  void invalidate();

  /// Makes the index describe `model` at `key`: rebuilds it when it was made for another pose
  /// (or invalidated); otherwise only instances whose mesh no longer fits (another mesh index,
  /// another vertex or face-slot count: the model was changed without the index) are rebuilt.
  /// With PoseDetail::Positions (what a cut needs) instances without grids are kept and new
  /// ones are built without; with Full every instance gets its grid.
  /// @pre when the index was built for this pose, every change to `model` since went through
  ///      `follow` (or was made by an operation given the index).
  void prepare(const Model& model, const PoseKey& key, PoseDetail detail = PoseDetail::Full);
  /// The operations' form, called first by each: prepare(model, PoseKey(animation, time,
  /// key().weights), detail): the weights set by hand stay.
  void prepare(const Model& model, int animation, float time, PoseDetail detail = PoseDetail::Full);

  /// The instance (node, primitive), or nullptr.
  PosedMesh* find(int node, int primitive);
  const PosedMesh* find(int node, int primitive) const;
  /// Number of indexed instances.
  std::size_t size() const { return instances_.size(); }
  /// Every instance, by (node, primitive).
  const std::map<std::pair<int, int>, PosedMesh>& instances() const { return instances_; }

  // --- upkeep by the operations (each O(edits)) ----------------------------------------------
  /// Follows `log`, made on the mesh of instance (node, primitive) (now `mesh`): PosedMesh::follow
  /// on that instance (an operation given the instance itself, such as tear_mesh, has done so).
  void follow(const Model& model, int node, int primitive, const SurfaceMesh& mesh, const EditLog& log);
  /// Follows a step's change to `model` (an undo or redo, now made; the index described the model
  /// before it): every instance of an edited primitive poses its new and rewritten vertices,
  /// drops the vertices and faces the step cut off, and files its faces again as the change says
  /// (posed_model_change.cpp). O(change), plus O(vertices) for bounds when the mesh shrank.
  /// A structural change invalidates the index (the next `prepare` rebuilds it).
  void follow(const Model& model, const ModelChange& change);
  /// The same, following a mapped structural step (ModelChange::mapped) too: the pose is taken
  /// again for the model's nodes (O(nodes + skins)); an instance whose content the step kept (at
  /// its new place) or that comes back from `stash` is kept when its node is posed as before
  /// (world matrix, joint matrices, morph weights), every other is built with `detail`; the
  /// instances of contents that left go into `stash` (what it held before is dropped; null: they
  /// are dropped). A kept instance keeps its arrays (the same buffers). An unmapped structural
  /// change invalidates the index.
  void follow(const Model& model, const ModelChange& change, PoseDetail detail, PoseStash* stash);
  /// (Re)indexes instance (node, primitive) of `model` from scratch (a new primitive, such as a
  /// drill's wall). O(its vertices + faces).
  void add(const Model& model, int node, int primitive);
  /// Drops instance (node, primitive); instances of later primitives of the node move down one.
  void erase_primitive(int node, int primitive);
  /// Drops every instance of `node` (it no longer draws a mesh).
  void erase_node(int node);
  /// Node `node` now draws mesh `mesh` (a copy of the one it drew: same vertices and faces).
  void rename_mesh(int node, int mesh);
  /// Node `piece` is a new piece of node `source` (a cut's piece node): it gets the weights set by
  /// hand for `source`, so the next build poses it at the same expression.
  void add_piece_node(int source, int piece);

 private:
  PosedMesh make_instance(const Model& model, int node, int primitive,
                          PoseDetail detail = PoseDetail::Full) const;
  void pose_instance(const SurfaceMesh& mesh, PosedMesh& inst, PoseDetail detail) const;
  /// Instance (node, primitive) of `model` made out of `source` (the instance before the step) as
  /// `origin` says: positions and linear maps of vertices with a source copied, the others posed.
  /// Equal to make_instance(model, node, primitive, Positions). Its arrays are those of one of
  /// `spare` (instances no longer drawn, taken by take_smallest_fit) when they hold its vertices,
  /// so their memory is reused; else new, with the piece's own room (piece_vertex_room,
  /// operation_room.h), so a small piece keeps no room of the content it was cut out of.
  PosedMesh derive_instance(const Model& model, int node, int primitive, const PosedMesh& source,
                            const PrimitiveOrigin& origin, std::vector<PosedMesh>& spare) const;
  void set_pose(const Model& model, const PoseKey& key);
  static std::size_t instance_count(const Model& model);
  const std::vector<glm::mat4>& joints_of(const Model& model, int node) const;

  bool valid_ = false;
  PoseKey key_;
  std::vector<glm::mat4> world_;               // every node's world matrix at the pose
  std::vector<std::vector<float>> weights_;    // every node's morph weights at the pose
  std::vector<std::vector<glm::mat4>> joints_;  // joint matrices of every skin at the pose
  std::map<std::pair<int, int>, PosedMesh> instances_;
};

}  // namespace deepcut
