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

}  // namespace deepcut
