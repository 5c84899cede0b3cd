// SPDX-License-Identifier: MIT
#pragma once
/// @file model_undo.h
/// Undo and redo of steps made on one model edited in place, holding what each step touched
/// instead of a copy of the model: a session's memory per local operation follows the edit, not
/// the mesh.
///
/// A `ModelRecorder` watches the model while an operation edits it (MeshObserver: MeshEditor
/// and SurfaceMesh tell it before an existing vertex or face is written, and hand it a primitive's
/// content before it is overwritten or destroyed). `finish` turns what it saw into a `ModelStep`:
/// - per primitive edited in place: its sizes before and after, the old values of the existing
///   vertices and faces the step rewrote (moved vertices, deleted marks), attributes it added or
///   removed; the elements it appended stay in the model (the step holds them while undone);
/// - a primitive the step replaced or removed (a swallowed primitive, a capped cut's source) kept
///   by move, and the model's small parts (nodes, meshes list, skins, animations, materials, ...)
///   before and after, when anything but the primitives' element data changed (`structure`),
///   shared where equal with the structural step made before it, which the caller names
///   (ModelRecorder::finish; a part the step did not change is not copied again);
/// - a primitive a cut took apart in place (the piece that keeps its arrays is compacted): which
///   piece holds each of its elements (a label of a few bits each) and the values of the slots
///   none holds that the step's own edits do not give back (deleted faces and unused vertices
///   older than the step); undo grows that piece back and writes the other pieces into it
///   (O(mesh), over the pool), redo compacts it again. Should a piece change later in the same
///   recording, the primitive is put back together first;
/// - the root extras (the history) as the text that differs: undo and redo apply it to the
///   model's root extras as the step left them (or found them), so every change to them must be
///   made within a recording (between steps, nothing may write them).
/// Undo and redo give back the model byte for byte. Images are never copied: operations leave
/// them alone (a step that changes them is not exact). A structural step says where each
/// primitive's content went (ModelChange::mapped: kept, left or arrived, tagged), made, undone
/// and redone, so followers keep what they drew of the contents it kept or brings back.
///
/// Operations append vertices and faces and mark faces deleted; they never compact a primitive
/// (but through the cut's split, which the recorder follows) or rewrite an existing element
/// behind the observer's back (writes go through MeshEditor, or
/// call SurfaceMesh::writing_vertex first). An operation may add attributes and remove the ones it
/// adds; of the attributes present before, it may remove only `f:cut_surface` (saved when the
/// recording begins).

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "deepcut/core/model.h"
#include "deepcut/core/model_change.h"

namespace deepcut {

/// One undoable step. Move-only; the step made last is undone first (each works on the state
/// the previous left).
class ModelStep {
 public:
  ModelStep();
  ~ModelStep();
  ModelStep(ModelStep&&) noexcept;
  ModelStep& operator=(ModelStep&&) noexcept;

  /// Makes `state` the model as one step (a change made outside the operations): the step holds
  /// the model it replaced (by move, no copy).
  static ModelStep replace(Model& model, Model state);

  /// Turns `model` (the state right after the step) back into the state before it.
  /// @returns what that changed.
  ModelChange undo(Model& model);
  /// Turns `model` (the state right before the step) into the state after it again.
  ModelChange redo(Model& model);

  /// What the step changed when it was made.
  const ModelChange& change() const;
  /// False when the recorder saw an edit it cannot take back (an attribute removed that was not
  /// saved, a primitive lost outside the model, images changed): undo would not be exact.
  bool exact() const;
  /// Bytes the step holds now (what it keeps of the state not current; capacity, and its share
  /// of what it shares with other steps).
  std::size_t bytes() const;
  /// Hands over the meshes the step holds (the primitives it made, while undone, and those it
  /// removed, while done), leaving a step that can no longer be undone or redone (both throw
  /// Error InvariantViolated): for a step being dropped, whose memory a later operation reuses
  /// (ModelRecorder::lend_spares).
  std::vector<SurfaceMesh> take_meshes();

 private:
  friend class ModelRecorder;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Watches a model while it is edited in place (see the file comment). Only one recorder at a
/// time per model; the model must outlive it, and no primitive mesh of it may leave the model
/// for a place that outlives the recording.
class ModelRecorder {
 public:
  explicit ModelRecorder(Model& model);
  ~ModelRecorder();
  ModelRecorder(const ModelRecorder&) = delete;
  ModelRecorder& operator=(const ModelRecorder&) = delete;

  /// The step the edits since the recorder was made form; the model is no longer watched.
  /// `last`: the structural step made last in the same history and done (the model as it left
  /// it but for local steps since), or nullptr: a structural step shares the model's small parts
  /// it did not change with that step's (a replace() step shares none); nothing is shared across
  /// histories.
  ModelStep finish(const ModelStep* last = nullptr);
  /// Memory the pieces a cut copies out of a primitive it takes apart may reuse instead of new
  /// memory: `source` is called once, the first time they need some, and returns meshes whose
  /// arrays nobody needs any more (ModelStep::take_meshes of steps being dropped); an array is
  /// reused only where it fits (take_smallest_fit), and what is not reused is freed with the
  /// recorder. The pieces' bytes are the same either way.
  void lend_spares(std::function<std::vector<SurfaceMesh>()> source);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace deepcut
