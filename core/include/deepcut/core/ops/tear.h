// SPDX-License-Identifier: MIT
#pragma once
/// @file ops/tear.h
/// Tear with a scalpel. The blade is a segment (handle, tip) at a start
/// pose and at an end pose; the quad H0 T0 T1 H1 it sweeps is the tear surface. Mesh edges crossing
/// the quad are split (once, shared by their faces), the vertices along the tear's interior are
/// duplicated so the two lips separate, and the lips are pushed apart along the quad's normal by an
/// opening that tapers to zero at both ends of every slit. Where the quad's boundary ends inside a
/// triangle, the slit ends at a new vertex inside it. A tear that reaches an existing tear's (or
/// any) boundary joins it, so strokes in a row give one slit.
///
/// Like Cut, predicates run on the posed positions (what the designer sees) and the resulting edge
/// parameters and barycentric coordinates are applied to the bind-space attributes; each new
/// vertex's bind position is its posed point on the quad unposed through its own blended skin
/// (PosedMesh::unpose), and each lip moves, posed, by its opening along the quad's normal.

#include <array>
#include <vector>

#include "deepcut/core/edit_log.h"
#include "deepcut/core/model.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/ops/op_status.h"
#include "deepcut/core/spatial_index.h"
#include "deepcut/core/surface_mesh.h"

namespace deepcut {

/// One pose of the scalpel's blade, world space.
struct Blade {
  glm::vec3 handle{0.0f};
  glm::vec3 tip{0.0f};
};

struct TearOptions {
  /// Opening width in model units: the gap between the lips where the slit is widest (each lip
  /// moves half of it). Negative (the default) means 5% of the mean blade length; 0 separates the
  /// lips topologically without moving them.
  float width = -1.0f;
  /// Snapping tolerance as a fraction of the model size (bounding-box diagonal of the posed
  /// positions): vertices closer to the tear surface count as on it, and no sliver thinner than
  /// this is made at the slit's ends. Default 1e-5.
  float relative_tolerance = 1e-5f;
};

/// The tear surface as planar triangles (world space). When the four corners H0 T0 T1 H1 are
/// coplanar within 1e-3 of the quad's size it is the planar quad, given as the two triangles
/// (H0, T0, T1) and (H0, T1, H1) projected onto the best-fit plane (they may overlap when the
/// blade's motion folds the quad; the surface is their union). Otherwise it is the quad folded
/// along the diagonal H0-T1: the same two triangles, each in its own plane. Degenerate triangles
/// (for example when the handle does not move) are left out.
/// @throws Error{InvalidArgument} for a zero-length or non-finite blade, identical start and end
///         poses, or a sweep that covers no area (the blade moving along its own line).
std::vector<std::array<glm::vec3, 3>> swept_quad_triangles(const Blade& start, const Blade& end);

/// The opening width `options` asks for with this blade (resolves the negative default).
float resolved_tear_width(const Blade& start, const Blade& end, const TearOptions& options);

struct TearResult {
  OpStatus status = OpStatus::Ok;
  /// Number of mesh edges the quad crossed (each split once): the paper's "intersection points".
  std::size_t intersection_points = 0;
  /// Vertices on the slits after the tear: both lips' copies and the end vertices, sorted.
  std::vector<VertexId> tear_vertices;
  /// Number of slits: connected pieces of this tear's path (one per layer the quad crosses).
  std::size_t slits = 0;
  /// Slits that close on themselves (the quad sliced all the way round a part): each leaves two
  /// boundary loops, and the part comes off.
  std::size_t closed_slits = 0;
  /// The opening width asked for (model units): TearOptions::width with the default resolved.
  float width = 0.0f;
  /// The opening achieved (world units): the widest gap between the two lips of any slit vertex
  /// after the moves were capped and halved (see the note on tear_mesh); at most `width`.
  float opening = 0.0f;
  /// Every change, in order: vertices added on edges and inside faces, faces replaced, lip
  /// vertices split (VertexSplit) and moved apart (VertexMoved).
  EditLog log;
};

/// Tears one mesh in place.
/// @param mesh         triangle mesh, edited through MeshEditor.
/// @param posed        the mesh at the pose the blade was placed against (posed_model.h): its
///                     posed positions (the predicates' geometry), linear skin maps and joint and
///                     world matrices (new vertices and the lips' moves go back to bind space
///                     through them, so the posed result is the slit and its opening exactly;
///                     `linear` empty: identity),
///                     bounds (the model size for the tolerance) and grid (the candidate faces,
///                     so the cost follows the tear, not the mesh). PosedMesh::at_positions(mesh) for a
///                     mesh on its own. On success it follows the tear's log (PosedMesh::follow),
///                     so it describes the torn mesh for the next operation.
/// @param start, end   the blade's two poses (world space).
/// @param options      see TearOptions (defaults: width 5% of the blade length, tolerance 1e-5).
/// @pre `posed` poses `mesh`: one posed position per vertex, `linear` empty or of the same size,
///      the grid over the live faces of `mesh` at `posed`.
/// @throws Error{InvalidArgument} for a degenerate blade or sweep (see swept_quad_triangles), a
///         non-finite width or tolerance, or a size mismatch.
/// @returns NoIntersection (mesh and `posed` untouched, log empty) when the quad crosses no part
///          of the surface.
/// @note Local: only faces the grid files along the quad's plane (and faces the tear made) are
///       examined.
/// @note Opening: each lip vertex moves by (width / 2) * sin(pi * s / L) along the quad normal
///       (s: arc length from the slit's nearer end, L: the slit's length; a slit that closes on
///       itself opens fully). No lip vertex moves further than the longest edge of its faces, and
///       a move that would flip a neighbouring face is halved until it does not, so coarse meshes
///       (or huge widths) open less than `width` rather than fold over: TearResult::opening says
///       how far they opened. The slits made (the topology) never depend on the width.
TearResult tear_mesh(SurfaceMesh& mesh, PosedMesh& posed, const Blade& start, const Blade& end,
                     const TearOptions& options = {});

struct ModelTearResult {
  OpStatus status = OpStatus::Ok;
  std::size_t intersection_points = 0;
  std::size_t tear_vertices = 0;
  std::size_t slits = 0;
  float width = 0.0f;    ///< asked for
  float opening = 0.0f;  ///< achieved: the largest TearResult::opening over the torn meshes
};

/// Tears every mesh instance of `model` posed at `time` of `animation` (-1: rest pose). Torn
/// primitives keep their skin, so the slit animates; a mesh shared by several instances is copied
/// for the instances the blade reaches. Instances the quad misses are left as they are.
/// @param posed  the model at this pose (posed_model.h): prepared for it first (PosedModel::prepare)
///               and kept up to date from the edit logs, so with a warm one the cost follows the
///               tear, not the mesh.
/// @throws Error{InvalidArgument} as tear_mesh, or for an animation index out of range.
ModelTearResult tear_model(Model& model, PosedModel& posed, const Blade& start, const Blade& end,
                           const TearOptions& options = {}, int animation = -1, float time = 0.0f);

/// tear_model on a PosedModel built for this call (the blade is checked first).
ModelTearResult tear_model(Model& model, const Blade& start, const Blade& end, const TearOptions& options = {},
                           int animation = -1, float time = 0.0f);

}  // namespace deepcut
