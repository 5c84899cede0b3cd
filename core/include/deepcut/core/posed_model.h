// SPDX-License-Identifier: MIT
#pragma once
/// @file posed_model.h
/// The model at one pose. For every mesh instance (node x primitive) of a model posed at one
/// animation time: the posed world position and the bind-to-world linear map of every vertex,
/// the exact bounds of those positions, and a `TriangleGrid` over the faces at them. Built once
/// per model state and pose (when the studio loads or poses the model, in the CLI before the
/// operation), handed to the operations, and updated from each operation's edit log, so an
/// operation costs what the tool touches, not the mesh. The updated posed model equals a fresh
/// build on the edited model (positions and bounds bit for bit, grids answering every query with
/// the same faces).

#include <cstddef>
#include <map>
#include <utility>
#include <vector>

#include "deepcut/core/edit_log.h"
#include "deepcut/core/model.h"
#include "deepcut/core/spatial_index.h"

namespace deepcut {

/// Gives every primitive of `model` room to grow by about an eighth (SurfaceMesh::reserve), as a
/// session does once after loading: the first operations then edit without reallocating whole
/// attribute arrays, and copies of the model (undo snapshots) keep the room. O(mesh), once.
void reserve_for_operations(Model& model);

/// One drawn primitive: primitive `primitive` of mesh `mesh`, instanced by node `node`.
struct PosedMesh {
  int node = -1, mesh = -1, primitive = -1;
  /// World position of every vertex slot of the primitive's mesh at the index's pose.
  std::vector<glm::vec3> posed;
  /// Linear part of each vertex's bind-to-world map (the weighted sum of its joint matrices
  /// when skinned, else the node's world matrix): `tear_mesh` maps its world moves to bind space
  /// through its inverse.
  std::vector<glm::mat3> linear;
  /// Bounds of every entry of `posed` (unreferenced vertices included): the model size the
  /// operations' tolerances are relative to.
  BoundingBox bounds;
  /// Grid over the live faces at `posed`.
  TriangleGrid grid;
  /// The node's world matrix and its skin's joint matrices at the pose (empty when not skinned):
  /// what `unpose` inverts, and how `follow` poses added and moved vertices as a fresh build would.
  glm::mat4 world{1.0f};
  std::vector<glm::mat4> joints;
  /// True for a mesh posed at given positions without a pose to invert (`at_positions`): the
  /// operations then leave new vertices at their interpolated bind positions.
  bool no_unpose = false;
  /// True for a mesh posed without a grid (PoseDetail::Positions): `grid` is empty, and
  /// `PosedModel::prepare` builds the instance again before an operation uses it.
  bool gridless = false;

  /// Bind position of vertex `v` of `surface` (skin weights already set) whose posed position is
  /// `p`: its blended skinning (or the world matrix) inverted in double precision; `p` itself
  /// where the inverse is not finite.
  glm::vec3 unpose(const SurfaceMesh& surface, VertexId v, const glm::vec3& p) const;

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

/// How much of each PosedMesh a build makes.
enum class PoseDetail {
  Full,       ///< positions, linear maps, bounds and grids: what the operations use
  Positions,  ///< positions, linear maps and bounds, no grids (`PosedMesh::gridless`): what
              ///< drawing a pose uses, cheap enough for every frame of a playback
};

class PosedModel {
 public:
  PosedModel() = default;

  /// Indexes every mesh instance of `model` posed at `time` of `animation` (-1: rest pose).
  /// O(vertices + faces), in parallel (O(vertices) for PoseDetail::Positions).
  /// @throws Error{InvalidArgument} for an animation index out of range.
  static PosedModel build(const Model& model, int animation, float time,
                          PoseDetail detail = PoseDetail::Full);

  /// Poses the same instances of `model` at `time` of `animation` with PoseDetail::Positions,
  /// reusing their arrays: positions, linear maps and bounds equal a fresh build's bit for bit;
  /// grids are dropped (`prepare` builds them again when an operation needs them). Builds from
  /// scratch when `model` no longer has the indexed instances. O(vertices), in parallel.
  /// @throws Error{InvalidArgument} for an animation index out of range.
  void repose(const Model& model, int animation, float time);

  /// Every node's world matrix at the pose (empty before a build).
  const std::vector<glm::mat4>& world() const { return world_; }

  /// True once built (and not invalidated).
  bool valid() const { return valid_; }
  /// True when built for this pose (`animation` -1 and an out-of-range time both as given).
  bool matches(int animation, float time) const { return valid_ && animation == animation_ && time == time_; }
  int animation() const { return animation_; }
  float time() const { return time_; }
  /// Forgets everything (the next `prepare` rebuilds).
  void invalidate();

  /// Makes the index describe `model` at this pose: rebuilds it when it was made for another
  /// pose (or invalidated); otherwise only instances whose mesh no longer fits (another mesh
  /// index, another vertex or face-slot count: the model was changed without the index) are
  /// rebuilt. The operations call this first.
  /// @pre when the index was built for this pose, every change to `model` since went through
  ///      `follow` (or was made by an operation given the index).
  void prepare(const Model& model, int animation, float time);

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
  /// (Re)indexes instance (node, primitive) of `model` from scratch (a new primitive, such as a
  /// drill's wall). O(its vertices + faces).
  void add(const Model& model, int node, int primitive);
  /// Drops instance (node, primitive); instances of later primitives of the node move down one.
  void erase_primitive(int node, int primitive);
  /// Drops every instance of `node` (it no longer draws a mesh).
  void erase_node(int node);
  /// Node `node` now draws mesh `mesh` (a copy of the one it drew: same vertices and faces).
  void rename_mesh(int node, int mesh);

 private:
  PosedMesh make_instance(const Model& model, int node, int primitive,
                          PoseDetail detail = PoseDetail::Full) const;
  void pose_instance(const SurfaceMesh& mesh, PosedMesh& inst, PoseDetail detail) const;
  void set_pose(const Model& model, int animation, float time);
  static std::size_t instance_count(const Model& model);
  const std::vector<glm::mat4>& joints_of(const Model& model, int node) const;

  bool valid_ = false;
  int animation_ = -1;
  float time_ = 0.0f;
  std::vector<glm::mat4> world_;               // every node's world matrix at the pose
  std::vector<std::vector<glm::mat4>> joints_;  // joint matrices of every skin at the pose
  std::map<std::pair<int, int>, PosedMesh> instances_;
};

}  // namespace deepcut
