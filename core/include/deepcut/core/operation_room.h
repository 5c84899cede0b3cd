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

/// The room of a posed array of a piece of `vertices` cut out of content of `source` vertices
/// (a derived piece's posed positions and linear maps): the room of half the source, or the
/// piece's own when larger. Set aside by an undo, each piece's arrays hold the smaller piece of
/// any later cut of that source (at most about half of it), however it splits it; a small piece
/// keeps no more than that alive (a spare is taken only up to twice the taker's own room).
inline std::size_t piece_vertex_room(std::size_t vertices, std::size_t source) {
  return operation_vertex_room(vertices > source / 2 ? vertices : source / 2);
}
/// The same for a piece's posed corner normals (`face_slots`, out of a source of `source_face_slots`).
inline std::size_t piece_corner_room(std::size_t face_slots, std::size_t source_face_slots) {
  return operation_corner_room(face_slots > source_face_slots / 2 ? face_slots : source_face_slots / 2);
}

}  // namespace deepcut
