// SPDX-License-Identifier: MIT
#pragma once
// The parts of an undo record (model_undo.h): one primitive's in-place edit, the model's small
// parts, and the root extras as the text that differs. Shared by the recorder and the step.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "deepcut/core/model.h"

namespace deepcut::undo {

/// Where a primitive sits: (mesh, primitive), or none (-1).
struct Place {
  int mesh = -1, primitive = -1;
  bool valid() const { return mesh >= 0; }
  bool operator==(const Place& o) const { return mesh == o.mesh && primitive == o.primitive; }
  bool operator<(const Place& o) const { return mesh != o.mesh ? mesh < o.mesh : primitive < o.primitive; }
};

/// An attribute array the step added or removed, held while it is not in the mesh.
struct HeldArray {
  int kind = 0;
  std::string name;
  std::unique_ptr<AttributeArrayBase> array;
};

/// One primitive's in-place edit. Existing elements it rewrote are swapped with the values kept
/// here (so undo and redo are the same swap); appended elements are cut off into `tail` on undo.
struct MeshDelta {
  std::size_t v0 = 0, f0 = 0, v1 = 0, f1 = 0;  // sizes before and after the step
  std::vector<std::uint32_t> vertices;         // existing vertices rewritten, increasing
  AttributeSet vertex_values;                  // element i: vertex vertices[i] in the other state
  std::vector<std::uint32_t> faces;            // existing faces rewritten, increasing
  std::vector<Triangle> corners;               // their corners, deleted marks, face and corner
  std::vector<std::uint8_t> deleted;           // attributes in the other state (3 corners each)
  AttributeSet face_values, corner_values;
  std::optional<MeshTail> tail;  // the appended elements, while undone
  std::vector<HeldArray> added;  // attributes the step added (held while undone)
  std::vector<HeldArray> removed;  // attributes the step removed (held while done)

  bool empty() const {
    return v0 == v1 && f0 == f1 && vertices.empty() && faces.empty() && added.empty() && removed.empty();
  }
  void undo(SurfaceMesh& mesh);
  void redo(SurfaceMesh& mesh);
  std::size_t bytes() const;

 private:
  void swap_existing(SurfaceMesh& mesh);
};

/// A primitive the step split in place (detail::SplitWatcher): the piece that kept its arrays
/// (`big`) and the pieces copied out of it hold its elements as the lists say; the rest (the slots
/// no piece holds: deleted faces, unused vertices) is kept here. Undo grows that piece back into
/// the primitive as it was at the split, reading the other pieces; redo compacts it again. The
/// pieces stand for the primitive only while they are as the split made them.
struct SplitPart {
  std::size_t vertex_count = 0, face_count = 0;             // the primitive's sizes at the split
  std::vector<std::vector<std::uint32_t>> vertices, faces;  // what each piece holds (increasing)
  std::size_t big = 0;
  std::array<std::vector<std::string>, 3> names;  // the attribute names at the split
  std::vector<std::uint32_t> rest_vertices, rest_faces;
  std::array<AttributeSet, 3> rest_values;  // theirs (3 corners per face)
  std::vector<Triangle> rest_corners;
  std::vector<std::uint8_t> rest_deleted;
  std::vector<std::size_t> fresh;  // each piece's index among the primitives the step made

  /// Keeps what `mesh` (at the split) holds outside the pieces of the lists.
  void take_rest(const SurfaceMesh& mesh);
  /// True when `piece` is still piece `k` as the split made it (sizes and attribute names).
  bool holds(std::size_t k, const SurfaceMesh& piece) const;
  /// True when `piece` holds at least what piece `k` held at the split: that many vertices and
  /// faces (or more, appended since) and every attribute the primitive had, of the same type.
  bool covers(std::size_t k, const SurfaceMesh& piece) const;
  /// The primitive at the split: `big_piece` (piece `big` as made, grown in place) and the other
  /// pieces (`pieces[k]`; piece `big`'s entry is not read).
  /// @throws Error{MissingAttribute} when a piece lacks an attribute.
  SurfaceMesh grow(SurfaceMesh&& big_piece, const std::vector<const SurfaceMesh*>& pieces) const;
  /// Piece `big` again, from the primitive at the split (compacted in place). Should it throw,
  /// `whole` is left as it was.
  SurfaceMesh shrink(SurfaceMesh&& whole) const;
  std::size_t bytes() const;
};

/// The model without its primitives' element data and images (each primitive's mesh keeps its
/// attribute names and types, no elements).
Model shell_of(const Model& model);
/// Makes `model` the shell's small parts, keeping its images; its primitives' meshes are the
/// shell's (empty) ones until the caller puts meshes back. Takes a copy the caller made (by move,
/// allocating nothing), so the copy can be made before any mesh leaves the model.
void restore_shell(Model& model, Model shell);
/// Bytes a shell holds (roughly: strings and arrays).
std::size_t shell_bytes(const Model& shell);

/// Text that changed between two versions: the common head and tail are not kept.
struct TextDelta {
  std::size_t head = 0, tail = 0;
  std::string before, after;  // the middles
  static TextDelta make(const std::string& before, const std::string& after);
  void undo(std::string& text) const;
  void redo(std::string& text) const;
  std::size_t bytes() const { return before.capacity() + after.capacity(); }
};

}  // namespace deepcut::undo
