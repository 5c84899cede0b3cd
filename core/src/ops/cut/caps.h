// SPDX-License-Identifier: MIT
#pragma once
// The cut's caps: the rim of each piece (its on-plane edges used by one of its faces) traced into
// loops and closed with triangles in the plane. Private to the cut (ops/cut/cut.cpp).

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "deepcut/core/mesh_editor.h"
#include "ops/common/posed_overlay.h"

namespace deepcut::detail {

/// What the cap of one piece is made from.
struct CapInput {
  glm::dvec3 normal{0.0}, point{0.0};  // the plane (unit normal)
  const PosedOverlay<glm::vec3>* posed = nullptr;
  /// Snapped side of every vertex (0: on the plane).
  const std::vector<std::int8_t>* sign = nullptr;
  /// The piece's faces with two or more corners on the plane (the only ones with rim edges).
  std::vector<FaceId> rim_faces;
  /// rim_halfedges(mesh, *this) where the caller has it already (make_caps finds it otherwise).
  std::optional<std::vector<std::pair<VertexId, VertexId>>> rim;
};

/// On-plane edges used by exactly one of `in.rim_faces`, as that face's halfedges (a -> b), in
/// face order; faces in `skip` (sorted) count as absent.
std::vector<std::pair<VertexId, VertexId>> rim_halfedges(const SurfaceMesh& mesh, const CapInput& in,
                                                         const std::vector<FaceId>& skip = {});

/// Caps every piece: pieces[p], from in[p], traced into loops and given cap faces (flagged
/// attr::kCutSurface, corner attributes set, corner morph deltas zero). A cap uses only rim
/// vertices, so it shares their morph targets' POSITION deltas and stays on the rim whatever the
/// weights. Faces of a piece lying in the plane are replaced by the cap when the rim closes
/// without them; open rims are not capped. The caps are planned first and their polygons
/// triangulated together (on the pool when they are big enough), then made one piece after
/// another: the same faces, ids and log as capping each piece in turn, whatever the thread count.
/// Returns true when every cap is whole fans: each polygon a loop of the piece's rim edges
/// without holes, given all its triangles, none degenerate; then at every rim vertex each run of
/// cap faces through one corner of a loop is one fan between the two rim edges of that corner.
bool make_caps(MeshEditor& editor, const std::vector<CapInput>& in, std::vector<std::vector<FaceId>>& pieces);

/// Tests: how the last make_caps on this thread made the polygons of its second cap, where its two
/// caps are the sides of one closed surface: `mirrored` taken from the first cap's triangles,
/// `clipped` clipped (both 0 otherwise).
struct CapMirrorStats {
  std::size_t mirrored = 0, clipped = 0;
};
CapMirrorStats& cap_mirror_stats();
/// Tests: whether make_caps may take the second cap's triangles from the first (default true; off,
/// every polygon is clipped). Process-wide.
void set_cap_mirroring(bool on);

}  // namespace deepcut::detail
