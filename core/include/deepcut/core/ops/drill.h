// SPDX-License-Identifier: MIT
#pragma once
/// @file ops/drill.h
/// Drill with a finite cylinder. Every surface layer the solid cylinder (axis A->B, radius r)
/// meets loses the surface inside it; the new rim lies on the cylinder. The circle is inserted into each crossed triangle in that triangle's own plane
/// (conforming insertion: crossed edges are split once and shared, rim points inside a triangle
/// are sampled at fixed angles around the axis, and each kept part of the triangle is
/// re-triangulated), so holes are round however coarse the mesh is, and UVs, normals and
/// colours are interpolated in each triangle's own parameterisation. Predicates run on the posed
/// positions; the edits are applied to the bind-space mesh (as for Cut).

#include <vector>

#include "deepcut/core/edit_log.h"
#include "deepcut/core/model.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/ops/op_status.h"
#include "deepcut/core/ops/parameter_name.h"
#include "deepcut/core/spatial_index.h"
#include "deepcut/core/surface_mesh.h"

namespace deepcut {

/// A finite solid cylinder: axis from `a` to `b`, radius `radius` (world space).
struct Cylinder {
  glm::vec3 a{0.0f};
  glm::vec3 b{0.0f, 1.0f, 0.0f};
  float radius = 0.1f;
};

struct DrillOptions {
  static constexpr int kMinRimEdgesMin = 3, kMinRimEdgesMax = 4096;  ///< min_rim_edges' range
  /// Rim edges of a hole whose layer the axis crosses: the circle is sampled at this many
  /// equal angles around the axis (edge crossings add more). Default 32; at least 3.
  int min_rim_edges = 32;
  /// Join the entry and exit rims with a tube on the cylinder (and close a hole that ends inside
  /// the model with a disk), faces flagged `attr::kCutSurface`. Default off.
  bool wall = false;
  /// Snapping tolerance as a fraction of the radius: vertices closer to the cylinder count as
  /// on it, and no rim vertex is made closer than this to another. Default 2e-3.
  float relative_tolerance = 2e-3f;
  /// apply_operation refuses (Error{InvalidArgument}) a drill that removes every triangle of an
  /// instance, rather than leave its node without a mesh. Default on; not a history key.
  bool refuse_swallowed_instances = true;
};

/// One rim: a chain of new boundary edges around a hole (closed unless the hole merged with an
/// earlier boundary, such as an older hole, a cut rim or a tear).
struct DrillHole {
  /// Rim vertices in boundary order (the kept surface on the left of each step).
  std::vector<VertexId> rim;
  bool closed = true;
  /// Turns around the axis: +1 where the axis enters the surface against its normal, -1 where
  /// it leaves, 0 for a notch the axis itself does not cross.
  int winding = 0;
  /// True when a wall (tube or disk) was attached to this rim.
  bool walled = false;
};

struct DrillResult {
  OpStatus status = OpStatus::Ok;
  std::vector<DrillHole> holes;
  /// Mesh edges the cylinder crossed (each split once): the paper's "intersection points".
  std::size_t intersection_points = 0;
  std::size_t triangles_removed = 0;
  std::size_t triangles_added = 0;
  /// Wall faces (tube and disks) among the added triangles.
  std::size_t wall_triangles = 0;
  /// Posed position of every vertex the drill added, in id order (vertex `first_new_vertex + i`),
  /// so callers can extend their posed positions and spatial index.
  std::vector<glm::vec3> added_posed;
  std::uint32_t first_new_vertex = 0;
  /// Old vertices the drill moved onto the cylinder, with their new posed positions (a vertex
  /// lying within a tenth of the rim spacing of the cylinder, whose edges would be crossed a
  /// hair from it, becomes a rim vertex itself instead of leaving needles; its bind position
  /// moves through its own skinning, logged as VertexMoved). Callers keeping their own posed
  /// positions set these in them before they follow the log (PosedMesh::follow does both).
  struct Moved {
    VertexId v;
    glm::vec3 posed{0.0f};
  };
  std::vector<Moved> moved;
  /// Every change, in order.
  EditLog log;
};

/// The smallest radius drill_mesh and drill_model accept for these axis end points and rim
/// edges: rim points must lie farther apart than the drill's absolute tolerance (1e-6 of the
/// axis' coordinates, a few float steps), or their float positions round onto one point or line.
float min_drill_radius(const Cylinder& cylinder, int min_rim_edges);

/// The drill's argument checks, which drill_mesh and drill_model make first, for front ends
/// that refuse a drill before they read a model (check_operation). `name` names the parameters
/// in the messages (default: the history keys, "radius").
/// @throws Error{InvalidArgument}: non-finite axis end points, "drill: radius must be positive",
///         "drill: the axis end points A and B coincide" (closer than 1e-7 of their
///         coordinates), "drill: min_rim_edges must be between 3 and 4096"
///         (DrillOptions::kMinRimEdgesMin/Max), a radius under min_drill_radius, or a
///         relative_tolerance outside [0, 0.1].
void check_drill_arguments(const Cylinder& cylinder, const DrillOptions& options, const ParameterName& name = {});

/// Drills one mesh in place.
/// @param mesh      triangle mesh, edited through MeshEditor.
/// @param posed     `mesh` posed (posed_model.h): its world positions, the grid over them (the
///                  cost grows with the hole, not the mesh), and the way back to bind space for
///                  new vertices (PosedMesh::unpose; none for PosedMesh::at_positions, the bind
///                  pose or positions given as they are). Update it afterwards from
///                  `result.log` (PosedModel::follow), or rebuild it.
/// @param cylinder  axis end points and radius, world space.
/// @param options   see DrillOptions (defaults: 32 rim edges, no wall, tolerance 2e-3 r).
/// @pre posed.posed.size() == mesh.vertex_count(), and its grid was built on those positions.
/// @throws Error{InvalidArgument} for a radius <= 0 or under min_drill_radius, A == B, non-finite
///         input, fewer than 3 rim edges, a negative tolerance or a size mismatch.
/// @returns NoIntersection (mesh untouched, log empty) when no surface lies inside the cylinder.
/// @note Surface is removed exactly where it lies inside the finite cylinder, so a layer that
///       B only partly reaches gets a notch closed by the end disk's plane (rim vertices there
///       lie on that plane, not on the cylinder). A hole whose layer the axis does not cross
///       (a notch in a grazed wall) gets the rim points its triangles meet, which can be fewer
///       than `min_rim_edges`. Walls close each connected shell on its own: the part of the
///       cylinder's surface (side and end disks) inside the shell, bounded by its rims, so blind
///       holes get their bottom, notches at an end plane their piece of the end disk, and
///       overlapping shells (a limb passing into a body) each stay closed. A shell that passes
///       through itself is walled per sheet; a rim that crosses itself (the posed surface
///       passing through itself) gets a wall folding with it. A shell with a boundary of its
///       own (an open sheet, a torn part) gets tubes between its rims but no cup out to an end
///       disk. Rims that are not closed (they joined a boundary the
///       input already had: an earlier hole, cut or tear without a wall) get no wall
///       (`DrillHole::walled`), nor do the rims of a sheet whose wall cannot be triangulated
///       exactly (rare: two rims touching at a vertex on the cylinder); those stay open, never
///       walled with a crack. Non-manifold edges are split like any other.
DrillResult drill_mesh(SurfaceMesh& mesh, const PosedMesh& posed, const Cylinder& cylinder,
                       const DrillOptions& options = {});

struct ModelDrillResult {
  OpStatus status = OpStatus::Ok;
  /// Rim vertex count of every hole, over all mesh instances.
  std::vector<std::size_t> rim_vertices;
  std::size_t intersection_points = 0;
  std::size_t triangles_removed = 0;
  std::size_t triangles_added = 0;
  std::size_t wall_triangles = 0;
  /// With `wall`: holes that got no wall (their rim joins an open boundary the input already had,
  /// their part was open already and the wall would be a cup to an end of the cylinder, or the
  /// surface there passes through itself more than twice).
  std::size_t unwalled_holes = 0;
};

/// Drills every mesh instance of `model` posed at `time` of `animation` (-1: rest pose). The
/// primitives are edited in place (their deleted faces and the wall's vertices stay as unused
/// slots until export compacts them); wall faces go to a new primitive, after the mesh's others,
/// with the "Cut surface" material; a primitive the cylinder swallows is dropped. Skins and
/// animations are kept, and new wall vertices are placed in bind space by inverting their
/// blended skinning. Meshes shared by several instances are copied before they change; an
/// instance the cylinder swallows whole loses its mesh (and skin) reference.
/// @param posed  the model at this pose (posed_model.h): prepared for it (rebuilt when it was
///               made for another), used for the posed positions and the candidate faces, and
///               updated from the edit logs, so with a warm one the cost grows with the hole,
///               not the mesh.
/// @throws Error{InvalidArgument} as drill_mesh, or for an animation index out of range.
ModelDrillResult drill_model(Model& model, PosedModel& posed, const Cylinder& cylinder,
                             const DrillOptions& options = {}, int animation = -1, float time = 0.0f);

/// drill_model on a posed model built for this pose (PosedModel::build): the same result.
ModelDrillResult drill_model(Model& model, const Cylinder& cylinder, const DrillOptions& options = {},
                             int animation = -1, float time = 0.0f);

}  // namespace deepcut
