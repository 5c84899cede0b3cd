// SPDX-License-Identifier: MIT
#pragma once
// The cut's first stage (ops/cut/cut.cpp): every vertex's signed distance to the plane at its
// posed position and its side, snapped to the plane within the tolerance. Private to the cut.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "deepcut/core/surface_mesh.h"
#include "ops/cut/face_lists.h"
#include "uninit_vector.h"

namespace deepcut::detail {

/// Per vertex of a mesh, as the cut classifies it. Vertices no face uses count for neither side:
/// distance 0, on the plane.
struct VertexSides {
  /// Signed distance to the plane (computed in float from the posed position).
  UninitVector<float> dist;
  /// Side: 1 where the normal points, -1 behind, 0 on the plane (within the tolerance).
  std::vector<std::int8_t> sign;
  /// The side as a bit (1 positive, 2 negative, 4 on the plane), so a face's corners or together
  /// into its kind.
  UninitVector<std::uint8_t> bits;
  /// True when some vertex lies on each side.
  bool both_sides = false;
};

/// Classifies every vertex of `mesh` at `posed` against the plane through `point` with unit
/// `normal`. The tolerance is `relative_tolerance` times the diagonal of the used vertices' posed
/// bounds: `used` flags them (a flag per vertex), or is nullptr when every vertex is used (the
/// cut's first guess, which its face scan then checks). `dist` and `sign` get room for `room`
/// vertices (the cut appends its new ones). Runs in parallel chunks; the result does not depend
/// on the thread count.
VertexSides classify_vertices(const SurfaceMesh& mesh, const std::vector<glm::vec3>& posed,
                              const glm::vec3& point, const glm::vec3& normal, float relative_tolerance,
                              std::size_t room, const std::uint8_t* used);

/// Flags in `used` (zeroed, a flag per vertex) the corners of every face slot of `mesh`.
void flag_used(const SurfaceMesh& mesh, std::uint8_t* used);

}  // namespace deepcut::detail
