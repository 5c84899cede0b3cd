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

/// The three attribute sets of a mesh by kind (0 vertex, 1 face, 2 corner).
AttributeSet& attrs(SurfaceMesh& mesh, int kind);
const AttributeSet& attrs(const SurfaceMesh& mesh, int kind);

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

/// The model without its primitives' element data and images (each primitive's mesh keeps its
/// attribute names and types, no elements).
Model shell_of(const Model& model);
/// Makes `model` the shell's small parts, keeping its images; its primitives' meshes are the
/// shell's (empty) ones until the caller puts meshes back.
void restore_shell(Model& model, const Model& shell);
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
