// SPDX-License-Identifier: MIT
#pragma once
// The cut's face lists (ops/cut/cut.cpp): the scan that files the faces off the plane by side,
// in runs, and the upkeep of sorted lists of face ids (merging, following moved faces). Private
// to the cut.

#include <cstdint>
#include <utility>
#include <vector>

#include "deepcut/core/surface_mesh.h"

namespace deepcut::detail {

/// A face's corners' side bits (the cut's per-vertex bits: 1 positive, 2 negative, 4 on the
/// plane) or'ed: 1 or 2, every corner on that side; with bit 4, a corner on the plane; 3 (or
/// 7), crossed.
inline unsigned corner_bits(const Triangle& t, const std::uint8_t* bits) {
  return bits[t[0].index] | bits[t[1].index] | bits[t[2].index];
}

/// The first face from `i` on (below `end`) whose corner bits are not `c` (or, with
/// kCheckDeleted, that is deleted): the end of a run of faces on one side. A loop on its own
/// (locals only), so the scan of a chunk stays tight.
template <bool kCheckDeleted>
std::uint32_t run_end(const SurfaceMesh& mesh, const std::uint8_t* bits, std::uint32_t i, std::uint32_t end,
                      unsigned c) {
  const Triangle* faces = mesh.faces().data();
  for (; i < end; ++i) {
    if (corner_bits(faces[i], bits) != c) break;
    if (kCheckDeleted && mesh.is_deleted(FaceId(i))) break;
  }
  return i;
}

/// The face ids [i, end) appended to `list` in one insert: constructed in place, with no zero
/// fill of the new elements first (a run can be most of the mesh).
void append_run(std::vector<FaceId>& list, std::uint32_t i, std::uint32_t end);

/// `piece` with each face moved (old, new: sorted by old) replaced by its new face, sorted. The
/// new faces are all at or above `first_new`; a piece sorted and below it keeps its order, so
/// only the new faces are sorted, after it.
void follow_moved_faces(const std::vector<std::pair<FaceId, FaceId>>& moved, FaceId first_new,
                        std::vector<FaceId>& piece);

/// `list` and `more` (both ascending) merged into `list`.
void merge_sorted(std::vector<FaceId>& list, const std::vector<FaceId>& more);

}  // namespace deepcut::detail
