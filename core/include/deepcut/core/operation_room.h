// SPDX-License-Identifier: MIT
#pragma once
// The room a primitive is given to grow (reserve_for_operations, posed_model.h): about an eighth
// more vertices and face slots, so the first operations after loading edit without reallocating
// whole arrays. The importer sizes the per-corner arrays it makes with the same room, so giving
// the room afterwards copies nothing.

#include <cstddef>

namespace deepcut {

inline std::size_t operation_vertex_room(std::size_t vertices) { return vertices + vertices / 8 + 1024; }
inline std::size_t operation_face_room(std::size_t face_slots) { return face_slots + face_slots / 8 + 2048; }
/// The room of a per-corner array (three corners per face slot): a corner per corner of the face room.
inline std::size_t operation_corner_room(std::size_t face_slots) { return 3 * operation_face_room(face_slots); }

/// The room of a posed array of a piece of `vertices` cut out of other content (a derived
/// piece's posed positions and linear maps): the piece's own, as any primitive's. Not the room of
/// the content it was cut out of: most pieces of a long session are small and outlive the step
/// that made them, and each would keep that room alive (keep_freed_memory makes it resident).
/// Set aside by an undo, a piece's arrays still hold a later cut's piece of up to their room and
/// down to about half of it (take_smallest_fit); a larger one gets new arrays.
inline std::size_t piece_vertex_room(std::size_t vertices) { return operation_vertex_room(vertices); }
/// The same for a piece's posed corner normals (`face_slots`): the piece's own corner room.
inline std::size_t piece_corner_room(std::size_t face_slots) { return operation_corner_room(face_slots); }

}  // namespace deepcut
