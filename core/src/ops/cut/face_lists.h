// SPDX-License-Identifier: MIT
#pragma once
// The cut's face lists (ops/cut/cut.cpp): the scan that files the faces by kind, those off the
// plane by side in runs, and the upkeep of sorted lists of face ids (merging, following moved
// faces). Private to the cut.

#include <cstddef>
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

/// Smallest parallel chunk of the cut's passes over every vertex or face (classification, the
/// face scan, flag_used): each costs a few instructions an element, so a range below it runs
/// inline on the caller. The pool's wake-up and join cost more than half of such a pass saves: a
/// 25k-triangle cut (about 13k vertices) on two threads took 0.83-0.85 ms against 0.72-0.74 ms
/// on one when its three passes were split at 4096.
inline constexpr std::size_t kMinPassGrain = 32768;

/// A flag per vertex (plain bytes, 0 or 1): some face slot uses it. The scan's threads may flag
/// one vertex together, so a flag is set and read through set_flag and flag_of, relaxed atomic
/// accesses to the byte (the __atomic builtins: C++17 has no std::atomic_ref), and the whole
/// buffer is cleared and checked as bytes (memset, memchr) only while no thread flags it.
inline void set_flag(std::uint8_t* flags, std::uint32_t i) {
  __atomic_store_n(flags + i, std::uint8_t{1}, __ATOMIC_RELAXED);
}
inline bool flag_of(const std::uint8_t* flags, std::size_t i) {
  return __atomic_load_n(flags + i, __ATOMIC_RELAXED) != 0;
}

/// The faces of one chunk of scan_faces, each list in id order.
struct ScannedFaces {
  std::vector<FaceId> crossed;   // corners on both sides
  std::vector<FaceId> touching;  // a corner on the plane, none on both sides
  std::vector<FaceId> clean[2];  // every corner on the positive (0) or the negative (1) side
  std::uint32_t end = 0;         // the chunk's faces are below this face slot
};

/// One pass over the face slots of `mesh` by the cut's side bits (one per vertex): the live
/// faces filed by kind, in parallel chunks (joined in order, they list the faces in id order;
/// the chunks may follow the thread count). Faces off the plane come in runs of one side
/// (neighbours in id order are neighbours on the surface): each run is found by a tight loop
/// and appended to its side's list whole. With `used` (zeroed, a flag per vertex), every face
/// slot's corners are flagged there too (deleted ones as well), so the cut needs no face pass
/// of its own to learn which vertices no face uses.
std::vector<ScannedFaces> scan_faces(const SurfaceMesh& mesh, const std::uint8_t* bits, std::uint8_t* used);

/// True when every one of the `count` flags is set (read once the threads that set them are
/// joined).
bool all_flagged(const std::uint8_t* flags, std::size_t count);

/// Sets the `count` flags to 0 (fresh ones, before any thread uses them), in parts over the pool.
void clear_flags(std::uint8_t* flags, std::size_t count);

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
