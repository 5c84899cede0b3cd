// SPDX-License-Identifier: MIT
#pragma once
// Conforming insertion of the cylinder's rim into the crossed triangles (the stages of
// drill_mesh before the walls; core/include/deepcut/core/ops/drill.h describes the algorithm).
// Private to the drill.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/spatial_index.h"
#include "geometry/polygon_triangulation.h"
#include "ops/drill/cylinder_section.h"
#include "ops/drill/posed_overlay.h"

namespace deepcut::drill {

// Old vertices within this many rim spacings of the cylinder's side, with crossings of two of
// their edges within kSnapClose rim spacings, are slid onto it (snap_shallow_vertices).
constexpr double kSnapBand = 0.1;
constexpr double kSnapClose = 0.5;

// How the rim faces and the wall sheets are triangulated before their Delaunay flips: every
// corner re-examined after each clip, holes joined by their shortest bridge.
constexpr geometry::TriangulationRules kRimTriangulation = {geometry::EarSearch::kExhaustive,
                                                            geometry::HoleBridge::kNearestPair};

/// True when vertex `v` lies deep inside the cylinder (CylinderFrame::deep_inside). Its posed
/// position is read straight from `posed` (a vertex never moved is found so without searching
/// the moved ones).
inline bool deep_vertex(const CylinderFrame& cyl, const PosedOverlay& posed, VertexId v) {
  return cyl.deep_inside(posed(v));
}

/// One rim: a chain of new boundary edges around a hole (DrillHole without the wall's answer).
struct Rim {
  /// Rim vertices in boundary order (the kept surface on the left of each step).
  std::vector<VertexId> vertices;
  bool closed = true;
  /// Turns around the axis (see DrillHole::winding).
  int winding = 0;
};

/// What inserting the rim did.
struct RimInsertion {
  /// Mesh edges the cylinder crossed (each split once).
  std::size_t crossings = 0;
  std::size_t removed = 0, added = 0;
  /// The corners not deep inside (deep_vertex) of the planned candidates that were removed and
  /// that none of their kept parts' faces use: corners inside the cylinder, and those of a candidate
  /// removed whole (within the tolerance, or degenerate). In candidate order, a corner once per
  /// candidate: off the rim, the only old vertices whose fans the insertion can part (drill.cpp).
  std::vector<VertexId> bared;
  /// Whether crossings were merged (a needle's two long edges crossed at one bind position): a
  /// merged vertex stands on two edges, so its kept parts need not meet around it.
  bool merged = false;
  /// Whether a kept part's triangulation dropped a degenerate ear (PlanChunk::gaps): a new
  /// vertex of that part may then stand between two fans.
  bool gaps = false;
};

/// Faces near the cylinder (far enough to hold every face around a vertex
/// snap_shallow_vertices may move), in processing order, found in the grid over the posed mesh.
std::vector<FaceId> find_candidates(const SurfaceMesh& mesh, const CylinderFrame& cyl,
                                    const PosedOverlay& posed, const TriangleGrid& index);

/// Slides old vertices lying a hair from the cylinder's side onto it (VertexMoved edits; their
/// new posed positions go to `posed`). Per candidate, `deep_corners` gets bit k set when its
/// corner k lies deep inside (deep_vertex) once the vertices have slid.
void snap_shallow_vertices(MeshEditor& editor, const CylinderFrame& cyl, PosedOverlay& posed,
                           const std::vector<FaceId>& candidates, std::vector<std::uint8_t>& deep_corners);

/// Splits the crossed edges of the candidates and re-triangulates the kept part of each one in
/// its plane (new vertices' posed positions go to `posed`); `deep_corners` as
/// snap_shallow_vertices gave them, one per candidate (asserted: they are indexed as the
/// candidates).
RimInsertion insert_rim(MeshEditor& editor, const CylinderFrame& cyl, PosedOverlay& posed,
                        const std::vector<FaceId>& candidates, const std::vector<std::uint8_t>& deep_corners);

/// The rims the edits so far left: boundary half-edges of the new faces (and of candidates left
/// alone) whose ends lie on the cylinder, chained. `copy_of` maps a pinch-split copy to its
/// original vertex.
std::vector<Rim> trace_rims(const SurfaceMesh& mesh, const EditLog& log, const CylinderFrame& cyl,
                            const PosedOverlay& posed, const std::vector<FaceId>& candidates,
                            const std::unordered_map<std::uint32_t, std::uint32_t>& copy_of);

}  // namespace deepcut::drill
