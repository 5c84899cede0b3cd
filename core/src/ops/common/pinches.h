// SPDX-License-Identifier: MIT
#pragma once
// Pinched vertices (a vertex where two or more fans of faces meet only at that point) split
// into one vertex per fan. Private to core: run by cut, tear and drill at the end of an edit,
// so an operation whose rim passes through a vertex (a saddle or a fold touching the tool within
// its tolerance) leaves a manifold vertex per sheet instead of a bow tie.

#include <utility>
#include <vector>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/spatial_index.h"

namespace deepcut::detail {

struct PinchSplits {
  /// (original, copy) for every copy made, in creation order (copy ids ascending).
  std::vector<std::pair<VertexId, VertexId>> copies;
  /// (old face, new face) for every face moved onto a copy (the old one is removed).
  std::vector<std::pair<FaceId, FaceId>> replaced;
  /// Live faces using a split vertex or one of its copies, after the split.
  std::vector<FaceId> around;
};

/// Vertices the edits so far used or freed (corners of added and removed faces, both ends of
/// vertex splits), sorted and unique: where an operation can have made a pinch.
std::vector<VertexId> edited_vertices(const EditLog& log);

/// Live faces of `mesh` using any of `vertices` (sorted), in id order: one pass over the faces.
std::vector<FaceId> faces_using(const SurfaceMesh& mesh, const std::vector<VertexId>& vertices);

/// Live faces using any of `vertices` (sorted): with `index` (a grid over the mesh as it was
/// before the edits in `log`, at `input_posed`), the faces the log added plus the grid's faces
/// around each older vertex (below `first_new_vertex`), so the cost follows the edit; without it,
/// faces_using (one pass over the mesh). A superset: split_pinched_vertices ignores the rest.
std::vector<FaceId> faces_around(const SurfaceMesh& mesh, const EditLog& log, const std::vector<VertexId>& vertices,
                                 std::uint32_t first_new_vertex, const TriangleGrid* index,
                                 const std::vector<glm::vec3>& input_posed);

/// Whether split_pinched_vertices(editor, candidates, incident) would split anything (it then
/// leaves the mesh as it is): read-only, so it can run beside other readers of the mesh.
bool any_pinched(const SurfaceMesh& mesh, const std::vector<VertexId>& candidates,
                 const std::vector<FaceId>& incident);

/// Splits each of `candidates` whose live faces form two or more fans (faces joined through an
/// edge at the vertex): the fan holding the lowest face id keeps the vertex, every other fan gets
/// a copy (MeshEditor::split_vertex, so attributes follow and the edit is logged) and its faces
/// are re-added on the copy with their corner and face attributes.
/// @param incident  every live face using a candidate (more faces are fine: they are ignored;
///                  deleted ones are skipped). A face missing here would split a vertex wrongly.
PinchSplits split_pinched_vertices(MeshEditor& editor, const std::vector<VertexId>& candidates,
                                   const std::vector<FaceId>& incident);

/// Rewrites a chain of vertices that follows mesh edges (a hole's rim, the kept surface on the
/// left of each step: a->b is a halfedge of a face) after split_pinched_vertices: where it passes
/// a split vertex it takes the copy whose faces hold both its steps there, else one of them.
void follow_pinch_splits(const SurfaceMesh& mesh, const PinchSplits& splits, std::vector<VertexId>& chain, bool closed);

}  // namespace deepcut::detail
