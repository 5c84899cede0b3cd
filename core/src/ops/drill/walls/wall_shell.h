// SPDX-License-Identifier: MIT
#pragma once
// The stages of one shell's wall (see wall.h), and the data they hand each other: the shell's
// rim loops in the wall plane (wall_loops.cpp), the sheets they form, the Steiner points of a
// sheet (wall_points.cpp), its triangulation (wall_sheet.cpp) and the faces made from it
// (wall_mesh.cpp). Private to the drill.

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "deepcut/core/mesh_editor.h"
#include "geometry/delaunay_flip.h"
#include "geometry/polygon_triangulation.h"
#include "geometry/predicates.h"
#include "ops/drill/posed_overlay.h"
#include "ops/drill/rim_insertion.h"
#include "ops/drill/walls/wall_map.h"

namespace deepcut::drill {

// Where a wall vertex lies on the cylinder (for its texture coordinates).
struct WallCoord {
  double theta, s;
  int where;
  VertexId v;
};

// What every shell's wall reads and adds to: the mesh (through the editor), the posed positions,
// the surface faces the drill kept near the cylinder, the rims, and the wall faces made so far.
struct WallContext {
  MeshEditor& editor;
  PosedOverlay& posed;
  const CylinderFrame& cyl;
  const std::vector<Rim>& rims;
  const std::vector<FaceId>& surface_faces;
  std::vector<std::pair<FaceId, int>> faces;  // wall faces: 0 tube, 1 disk
  std::unordered_map<std::uint32_t, WallCoord> coords;
  std::size_t removed = 0, added = 0;
};

// One shell's rims in the wall plane.
struct WallShell {
  WallMap map;                        // its frame (reversed when more rim points lie at B) and plane
  double tol = 0.0;                   // on the cylinder within this
  std::vector<std::size_t> hole_ids;  // its rims
  std::vector<WallPt> pts;            // rim points, then the Steiner points of its sheets
  std::vector<glm::dvec2> xy;         // pts in the plane (map_points)
  double s_lo = kInf, s_hi = -kInf;   // extent of the rims along the axis
  Loops rim_loops;
  std::vector<std::size_t> loop_hole;                       // the rim each loop comes from
  std::vector<std::pair<std::size_t, geometry::LocalTri>>
      lobe_tris;                                            // folds: loop, triangle (indices into pts)
  std::vector<int> sheet;                                   // per loop: 0 or 1

  void map_points() {
    xy.clear();
    for (const auto& w : pts) xy.push_back(map.to_plane(w));
  }
  /// The loops of sheet `k`, plus loop `extra`.
  Loops sheet_loops(int k, std::size_t extra) const {
    Loops ls;
    for (std::size_t li = 0; li < rim_loops.size(); ++li)
      if (sheet[li] == k || li == extra) ls.push_back(rim_loops[li]);
    return ls;
  }
};

// wall_loops.cpp
/// The shell's rims as loops in the plane (run the other way, split where a rim touches itself),
/// folded where they cross themselves, and split into sheets. False when it cannot be walled.
bool shell_loops(WallShell& shell, const WallContext& ctx);
/// Short-cuts loops that cross themselves; the lobes cut off go to `lobes` (loop, triangle).
bool fold_loops(const std::vector<glm::dvec2>& xy, Loops& loops,
                std::vector<std::pair<std::size_t, geometry::LocalTri>>& lobes);

// wall_points.cpp
using Segments = std::vector<std::pair<std::uint32_t, std::uint32_t>>;
/// What a sheet reaches along the axis.
struct SheetExtent {
  double lo = 0.0, hi = 0.0;
  bool touches_a = false, touches_b = false;
};
/// Steiner candidates on the cylinder's surface, away from the rims (rows, rings, disk centres).
std::vector<WallPt> steiner_candidates(const WallShell& shell, const Loops& loops, const Segments& segments,
                                       const SheetExtent& extent, const SurfaceMesh& mesh);

// wall_sheet.cpp
/// One sheet's region, triangulated and added (nothing is added when it returns false).
bool wall_sheet(WallShell& shell, WallContext& ctx, const Loops& sheet_loops, int sheet_id, bool open_shell);

// wall_mesh.cpp
/// Adds the sheet's triangles (indices into shell.pts) as faces, creating the Steiner vertices;
/// false (nothing added) when a face would make an edge non-manifold.
bool emit_sheet(WallShell& shell, WallContext& ctx, const std::vector<geometry::LocalTri>& wall_tris);
/// Texture coordinates, normals, tangents and colours of the wall faces, and their flag.
void finish_wall_attributes(WallContext& ctx);

}  // namespace deepcut::drill
