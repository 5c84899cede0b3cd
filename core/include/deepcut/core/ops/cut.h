// SPDX-License-Identifier: MIT
#pragma once
/// @file ops/cut.h
/// Cut by an infinite plane. Predicates run on the posed positions (what the designer sees); each
/// new rim vertex is the posed point where the plane crosses an edge, unposed through its own
/// blended skin (PosedMesh::unpose), so the cut lands exactly where it was placed and the pieces
/// still animate. The stages are laid out in docs/architecture.md.

#include <cstdint>
#include <memory>
#include <vector>

#include "deepcut/core/edit_log.h"
#include "deepcut/core/model.h"
#include "deepcut/core/ops/op_status.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/surface_mesh.h"

namespace deepcut {

namespace detail {
struct CutSides;
}  // namespace detail

enum class CutKeep { Both, Positive, Negative };

struct CutOptions {
  /// Snapping tolerance as a fraction of the model size (bounding-box diagonal of the posed
  /// positions): vertices closer to the plane count as on it and no sliver thinner than this is
  /// made. Default 1e-5.
  float relative_tolerance = 1e-5f;
  /// Which side(s) to keep (default both, as separate pieces).
  CutKeep keep = CutKeep::Both;
  /// Split each side further into its connected components (default off).
  bool split_components = false;
  /// Close each rim loop of a closed piece with a triangulated cap (default off).
  bool cap = false;
};

struct CutResult {
  OpStatus status = OpStatus::Ok;
  /// Number of mesh edges the plane crossed (each split once): the paper's "intersection points".
  std::size_t intersection_points = 0;
  /// Vertices on the plane after the cut, positive side's copies included.
  std::vector<VertexId> rim_vertices;
  /// Live faces of each output piece (side, then component when requested), in a stable order.
  std::vector<std::vector<FaceId>> pieces;
  /// Side of each piece: +1 where the normal points, -1 behind the plane.
  std::vector<int> piece_sides;
  /// Every change, in order (vertex splits separate the two sides topologically).
  EditLog log;

 private:
  friend struct detail::CutSides;  // private to core: the cut writes it, the model surgery reads it
  /// Side of every vertex where the pieces are the sides (no caps, no components): that of the
  /// live faces using it (+1 or -1, as piece_sides), 0 where no live face does (a vertex of a
  /// side the cut dropped keeps that side: no piece has it). Empty otherwise, for a mesh with
  /// deleted faces, and for the rare cut that merged a needle's two crossings. What the mesh
  /// surgery splits the pieces by, without a pass over their faces.
  std::vector<std::int8_t> vertex_sides_;
};

/// The cut's argument check, which cut_mesh makes first, for front ends that refuse a cut before
/// they read a model (check_operation).
/// @throws Error{InvalidArgument}: "cut: the plane normal is zero", "cut: the plane normal is not
///         finite" or "cut: the plane point is not finite".
void check_cut_plane(const Plane& plane);

/// Cuts one mesh in place. `posed.posed` gives the world position of every vertex (the pose the
/// plane was placed against). The sides end up topologically separate (rim vertices are split),
/// so pieces are connected components of the result.
/// @param mesh     triangle mesh, edited through MeshEditor.
/// @param posed    the mesh at the pose (the cut reads `posed.posed`). On return it follows the
///                 cut's log (PosedMesh::follow): the vertices the cut added (edge points where the
///                 plane crossed, side copies) posed as a fresh build would, bounds and grid updated.
/// @param plane    point and normal (world space); the normal need not be unit.
/// @param options  see CutOptions (defaults: both sides, no cap, tolerance 1e-5 of model size).
/// @pre posed.posed.size() == mesh.vertex_count().
/// @throws Error{InvalidArgument} for a zero or non-finite normal or point, or a size mismatch.
/// @returns NoIntersection (mesh and `posed` untouched, log empty) when every vertex lies on one
///          side.
/// @note Non-manifold edges are split like any other (each face keeps its own half), so
///       non-manifold input is handled, not rejected.
CutResult cut_mesh(SurfaceMesh& mesh, PosedMesh& posed, const Plane& plane, const CutOptions& options = {});

/// Convenience: cut_mesh with posed positions at hand (`mesh.positions()` for the bind pose),
/// read only. Same result.
CutResult cut_mesh(SurfaceMesh& mesh, const std::vector<glm::vec3>& posed, const Plane& plane,
                   const CutOptions& options = {});

struct ModelCutResult {
  OpStatus status = OpStatus::Ok;
  std::size_t intersection_points = 0;
  std::size_t rim_vertices = 0;
  /// One entry per output piece node: the node index in the cut model.
  std::vector<int> piece_nodes;
  /// Where each piece primitive's elements came from in the primitive it was cut out of (the
  /// rim's new and snapped vertices and the faces around them excepted): what a front end hands
  /// its followers as ModelChange::origins, so they copy what they drew instead of redrawing it.
  /// Given for the meshes an undo record watches (ModelRecorder: a front end that follows the
  /// steps); empty for a one-off cut, which spares the passes.
  std::vector<std::shared_ptr<const PrimitiveOrigin>> origins;
};

/// Cuts every mesh instance of `model` posed at `time` of `animation` (-1: rest pose). Each
/// output piece becomes its own node and mesh bound to the original skin. Instances the plane
/// misses are left as they are.
/// @param posed  the model at that pose: prepared first (PosedModel::prepare, so it is rebuilt
///               when made for another pose). The instances the cut rewrote or dropped leave it,
///               and piece nodes are added, so the next `prepare` indexes what changed (it
///               rebuilds when nodes were added); the other instances stay as they were.
/// @throws Error{InvalidArgument} as cut_mesh, or for an animation index out of range.
ModelCutResult cut_model(Model& model, PosedModel& posed, const Plane& plane, const CutOptions& options, int animation,
                         float time);

/// Convenience: cut_model with a posed model built for the call.
ModelCutResult cut_model(Model& model, const Plane& plane, const CutOptions& options = {}, int animation = -1,
                         float time = 0.0f);

}  // namespace deepcut
