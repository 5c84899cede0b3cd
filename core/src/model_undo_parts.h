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
#include "model_undo_labels.h"
#include "ops/common/model_surgery_in_place.h"

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
/// (`big`) and the pieces copied out of it hold its elements as the labels say; of the slots no
/// piece holds (deleted faces, unused vertices) the values undo needs are kept here. Undo grows
/// that piece back into the primitive as it was at the split, reading the other pieces; redo
/// compacts it again. The pieces stand for the primitive only while they are as the split made
/// them.
struct SplitPart {
  PieceLabels vertices, faces;  // which piece holds each element of the primitive at the split
  std::size_t big = 0;
  std::array<std::vector<std::string>, 3> names;  // the attribute names at the split
  // The slots no piece holds that the step's delta does not give back (see take_rest), and
  // their values (3 corners per face).
  std::vector<std::uint32_t> rest_vertices, rest_faces;
  std::array<AttributeSet, 3> rest_values;
  std::vector<Triangle> rest_corners;
  std::vector<std::uint8_t> rest_deleted;
  std::vector<std::size_t> fresh;  // each piece's index among the primitives the step made

  std::size_t pieces() const { return vertices.pieces(); }
  /// Keeps what `mesh` (at the split) holds outside the pieces that undo needs: not the slots
  /// `at_split` (the step's edits up to the split) rewrote or appended, whose values before the
  /// step it gives back itself (their values at the split are the rest's, which redo's
  /// compaction drops again). Those slots' values are left unspecified when the primitive grows
  /// back.
  void take_rest(const SurfaceMesh& mesh, const MeshDelta& at_split);
  /// True when `piece` is still piece `k` as the split made it (sizes and attribute names).
  bool holds(std::size_t k, const SurfaceMesh& piece) const;
  /// True when `piece` holds at least what piece `k` held at the split: that many vertices and
  /// faces (or more, appended since) and every attribute the primitive had, of the same type.
  bool covers(std::size_t k, const SurfaceMesh& piece) const;
  /// The lists of each piece's elements, the rest last (PieceLabels::lists): made before any
  /// mesh leaves the model, so that undo and redo allocate nothing that large once one has.
  struct Lists {
    std::vector<std::vector<std::uint32_t>> vertices, faces;
  };
  /// Every piece's and the rest's (what grow reads).
  Lists lists() const;
  /// Piece `big`'s only, the others empty (what shrink reads).
  Lists big_lists() const;
  /// The primitive at the split (but the slots take_rest left out): `big_piece` (piece `big` as
  /// made, grown in place) and the other pieces (`pieces[k]`; piece `big`'s entry is not read);
  /// `lists` from lists().
  /// @throws Error{MissingAttribute} when a piece lacks an attribute.
  SurfaceMesh grow(SurfaceMesh&& big_piece, const std::vector<const SurfaceMesh*>& pieces,
                   const Lists& lists) const;
  /// Piece `big` again, from the primitive at the split (compacted in place); `lists` from
  /// big_lists(). Should it throw, `whole` is left as it was.
  SurfaceMesh shrink(SurfaceMesh&& whole, const Lists& lists) const;
  std::size_t bytes() const;
};

/// What `part`'s primitive grows by when it grows back (detail::expand_piece): the pieces
/// (`pieces[k]`, piece `big`'s not read), the rest, and copies of the other pieces' first
/// elements for the slots take_rest left out. They add up to the growth (each array then grows
/// by copies, not by a slow fill of default values) whenever the other pieces hold as many
/// vertices and as many faces as those slots. `lists` from SplitPart::lists().
std::vector<detail::Room> rooms_to_grow(const SplitPart& part, const std::vector<const SurfaceMesh*>& pieces,
                                        const SplitPart::Lists& lists);

/// The model without its primitives' element data and images (each primitive's mesh keeps its
/// attribute names and types, no elements).
Model shell_of(const Model& model);
/// Makes `model` the shell's small parts, keeping its images; its primitives' meshes are the
/// shell's (empty) ones until the caller puts meshes back. Takes a copy the caller made (by move,
/// allocating nothing), so the copy can be made before any mesh leaves the model.
void restore_shell(Model& model, Model shell);
/// Bytes a shell holds (roughly: strings and arrays), its primitives' meshes (capacity) included:
/// a whole model's too.
std::size_t shell_bytes(const Model& shell);

/// A shell (shell_of) as a structural step keeps it: without the root extras and the primitives'
/// attribute layouts (the meshes undo and redo put back bring theirs), in parts that change
/// apart: each node, each mesh, the animations, the rest. A part equal to the same part of the
/// shell `like` (the node or mesh at the same index), one kept in the same history, is shared
/// with it, not copied: a step's shell after shares what the step left alone with its shell
/// before, and that one with the shell after of the structural step made last (mostly equal: a
/// cut changes a few nodes and meshes and adds some), so a session's cuts keep about one copy of
/// each node and mesh and one of the animations in all. Equal as same_structure says (floats
/// bit for bit).
class KeptShell {
 public:
  KeptShell() = default;
  /// `like`: the shell to share equal parts with, or nullptr.
  KeptShell(Model shell, const KeptShell* like);
  /// A copy of the shell, for restore_shell (root extras empty, primitives' meshes empty).
  Model model() const;
  /// This shell's share of the bytes of its parts (each part's bytes over its holders).
  std::size_t bytes() const;

 private:
  std::array<std::shared_ptr<const Model>, 2> slices_;  // the animations; the rest
  std::vector<std::shared_ptr<const Node>> nodes_;
  std::vector<std::shared_ptr<const Mesh>> meshes_;
};

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
