// SPDX-License-Identifier: MIT
#pragma once
// The drill's wall: closes the rims of each connected shell with the part of the cylinder's
// surface (side and end disks) inside that shell. The surface is mapped to one plane
// (wall_map.h), where the shell's rims are nested loops; the region inside the shell is where
// their winding number plus a constant is 1, triangulated as outer loops with holes, with Steiner
// points on rows over the side and rings over the disks. core/include/deepcut/core/ops/drill.h
// says which rims get a wall. Private to the drill.

#include <cstddef>
#include <vector>

#include "deepcut/core/mesh_editor.h"
#include "ops/drill/cylinder_section.h"
#include "ops/drill/posed_overlay.h"
#include "ops/drill/rim_insertion.h"

namespace deepcut::drill {

struct WallResult {
  /// Per rim: true when the wall closes it.
  std::vector<char> walled;
  /// Wall faces added (flagged attr::kCutSurface), and surface faces removed (an island whose
  /// corners all lie on the rims goes with its mirror image).
  std::size_t wall_triangles = 0, triangles_removed = 0;
};

/// Walls the shells of `rims` in `editor`'s mesh. New wall vertices get posed positions in
/// `posed` (and bind positions through its unposer, which subtracts their morph offset); their
/// attributes, skin weights and morph POSITION deltas are blended from the two nearest rim
/// vertices, so a wall meets its rims (sharing their vertices) whatever the morph weights. Wall
/// faces get UVs, normals, tangents and colours, and zero corner morph deltas.
/// @param cyl            the drill's cylinder (its tolerance says what lies on it).
/// @param rims           rims of holes in the mesh, in boundary order with the kept surface on the
///                       left of each step; only closed ones are walled.
/// @param surface_faces  faces of the surface near the rims the drill did not add (deleted ones
///                       are skipped): the wall never repeats their edges.
/// @pre every rim vertex lies on the cylinder's side or end disks (within 2 tolerances), and the
///      posed positions of `posed` cover every vertex.
WallResult build_drill_walls(MeshEditor& editor, const CylinderFrame& cyl, const std::vector<Rim>& rims,
                             PosedOverlay& posed, const std::vector<FaceId>& surface_faces);

}  // namespace deepcut::drill
