// SPDX-License-Identifier: MIT
#pragma once
// A piece of a mesh made from the mesh's own arrays, and the mesh made back from its pieces, in
// place (private to core): the model surgery's split (split_disjoint) compacts the piece that
// keeps the mesh's arrays, and an undo record (model_undo.h) that kept only what the pieces do
// not hold grows that piece back into the mesh and compacts it again on redo. The bytes move
// inside the arrays they are in (a compaction allocates no array; growing a piece back reallocates
// an array only where its capacity does not hold the mesh), stretch by stretch, each stretch in
// chunks over the pool across every array at once (the same bytes whatever the threads).

#include <array>
#include <cstdint>
#include <vector>

#include "deepcut/core/surface_mesh.h"

namespace deepcut::detail {

/// The three attribute sets of a mesh by kind (0 vertex, 1 face, 2 corner), and how many
/// elements of each a vertex (1), a face (1) or a face's corners (3) are.
const AttributeSet& set_of(const SurfaceMesh& mesh, int kind);
AttributeSet& set_of(SurfaceMesh& mesh, int kind);
inline std::size_t group_of(int kind) { return kind == 2 ? 3 : 1; }

/// The room each array of a split's piece has past its `count` vertices or face slots (a piece
/// copied out gets it reserved; one compacted in place keeps that much of its pages resident):
/// an eighth more, as the operations' room (operation_room.h), with a smaller fixed part. A
/// session leaves many small pieces (176 after 200 operations on 1M triangles, a few thousand
/// faces each); with the operations' 1024 vertices and 2048 face slots per array each, their room
/// held about 55 MiB resident. So a piece's first edit that adds more than `count / 8 + 64`
/// elements outgrows it: AttributeArrayBase::room_for then moves each array into memory of twice
/// its size, copying the piece once; cheap for the small pieces the fixed part was cut for (a few
/// thousand elements), and a large piece's eighth is itself large.
/// The posed model's piece rooms (operation_room.h, piece_vertex_room and piece_corner_room) are
/// not this: they are the operations' room of half the source, so that posed arrays set aside by
/// an undo hold the smaller piece of any later cut of that source, and they keep the operations'
/// fixed part; they are prefaulted, and sized by the posed side, not here.
inline std::size_t split_room(std::size_t count) { return count + count / 8 + 64; }

/// Elements per task of a pass over the pool that reads or writes one small value per element
/// (an index list, a renumbered triangle): enough to outweigh handing the task out.
constexpr std::size_t kIndexGrain = 65536;

/// Length of the leading run of an increasing `keep` that stays put (keep[i] == i): the elements
/// an in-place move by `keep` leaves where they are.
std::size_t staying_put(const std::vector<std::uint32_t>& keep);

/// Groups of `width` bytes moved by an increasing `keep`, groups `begin .. end - 1`: gathering
/// (`spread` false), group i of `dst` gets group keep[i] of `src`; spreading, group keep[i] of
/// `dst` gets group i of `src`. In place (dst == src) keep[i] >= i, so a gather runs forward and
/// a spread backward, and neither reads a group it wrote.
struct GroupCopy {
  unsigned char* dst;
  const unsigned char* src;
  std::size_t width;
  const std::uint32_t* keep;
  std::size_t begin, end;
  bool spread;
};

/// The moves of an in-place compaction, planned before it starts: rounds run one after the other,
/// the copies of a round at once over the pool. Running a plan allocates nothing, so a mesh taken
/// apart is never left half compacted for want of memory. The plan holds the addresses of the
/// mesh's arrays and the lists: valid while neither is resized.
struct MovePlan {
  std::vector<std::vector<GroupCopy>> rounds;
};

/// The moves that make `mesh` its piece of the (increasing) `vertices` and `faces`.
MovePlan plan_compaction(SurfaceMesh& mesh, const std::vector<std::uint32_t>& vertices,
                         const std::vector<std::uint32_t>& faces);

/// `mesh` becomes its piece of the (increasing) `vertices` and `faces` (live faces whose corners
/// are among `vertices`): every array compacted in place by `plan` (plan_compaction, with the same
/// lists), then the triangles renumbered by `rank` (`rank[v]`: vertex v's index in `vertices`,
/// read for those vertices only). Allocates nothing. The arrays keep their capacity, but their
/// pages past the piece's room (split_room) are handed back to the system
/// (release_room, process_memory.h): they held the mesh's other elements.
void compact_piece(SurfaceMesh& mesh, const MovePlan& plan, const std::vector<std::uint32_t>& vertices,
                   const std::vector<std::uint32_t>& faces, const std::uint32_t* rank);

/// Elements to write into a mesh's slots: `values` (vertices, faces, 3 corners per face; the
/// mesh's attribute names at least) and `triangle_count` `triangles`, whose corners are mesh
/// vertices, or indices into `vertex_map` when it is given (a piece's own numbering).
struct Elements {
  std::array<const AttributeSet*, 3> values{};
  const Triangle* triangles = nullptr;
  const std::vector<std::uint32_t>* vertex_map = nullptr;
  std::size_t triangle_count = 0;
};

/// The first `vertices` vertices and `faces` faces of some elements (`values`, `triangles`),
/// copied to make the room a piece grows into: what the other pieces and the slots none holds
/// bring, whose values overwrite them right after, or copies that only make up the room (their
/// slots' values are written later or left unspecified).
struct Room {
  std::array<const AttributeSet*, 3> values{};
  const Triangle* triangles = nullptr;
  std::size_t vertices = 0, faces = 0;
};

/// The inverse of compact_piece: `piece` (exactly `vertices.size()` vertices and `faces.size()`
/// faces) grown in place to `vertex_count` vertices and `face_slots` live faces, its vertex i
/// moved to `vertices[i]`, face i to `faces[i]` (its corners naming `vertices` again). The other
/// slots are left for `scatter` (their values are unspecified). The arrays grow by copies of
/// `rooms` (where they make up the growth, else by default values). No allocation where the
/// arrays' capacity holds the sizes (a piece compact_piece made keeps the mesh's; the pages it
/// handed back are faulted in again as the arrays grow into them).
void expand_piece(SurfaceMesh& piece, const std::vector<std::uint32_t>& vertices,
                  const std::vector<std::uint32_t>& faces, std::size_t vertex_count, std::size_t face_slots,
                  const std::vector<Room>& rooms);

/// Vertex i of `from` written to vertex `vertices[i]` of `mesh`, face i (its attributes, corners
/// and triangle) to face `faces[i]`, over the pool. The faces' deleted marks are left as they are.
/// @throws Error{MissingAttribute} when `from` lacks one of the mesh's attributes (or has it with
/// another element size), Error{InvalidArgument} when it holds fewer elements than the lists
/// name; nothing is written then.
void scatter(SurfaceMesh& mesh, const Elements& from, const std::vector<std::uint32_t>& vertices,
             const std::vector<std::uint32_t>& faces);

}  // namespace deepcut::detail
