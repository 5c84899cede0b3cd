// SPDX-License-Identifier: MIT
#pragma once
/// @file session.h
/// A modelling session without a window: the model as opened and its current state, the
/// operations made since it was opened, applying one operation or a whole history, editing a past
/// operation and re-running the ones after it, the undo/redo stack, and the posed model the
/// operations share (posed_model.h). The studio shows what a Session holds; `deepcut apply` runs
/// a history through one. No Qt and no VTK here. See docs/studio.md (History panel, undo) and
/// docs/cli.md ("History files").
///
/// The session owns ONE live model, edited in place: an operation edits it, and its undo step
/// (model_undo.h) keeps only what the operation touched (old values of the elements it rewrote,
/// the primitives it replaced, the small parts when they changed), so memory per local operation
/// follows the edit, not the mesh. Undo and redo turn the live model back and forth, byte for
/// byte. Each step says what it changed (`ModelChange`), so the studio's scene and the posed
/// model follow in O(change).

#include <cstddef>
#include <functional>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "deepcut/core/model.h"
#include "deepcut/core/model_change.h"
#include "deepcut/core/model_undo.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/posed_model.h"

namespace deepcut::session {

/// One operation made since the model was opened, as it last ran: `status` Ok, NoIntersection
/// (it no longer applies and was skipped), or `error` set (it failed and was skipped).
struct OperationEntry {
  Operation operation;
  OpStatus status = OpStatus::Ok;
  std::string error;
  bool applied() const { return status == OpStatus::Ok && error.empty(); }
};

/// What `Session::apply` did: the operation's result, what it changed in the model (empty for a
/// miss) and how long it took (the undo record included).
struct Applied {
  OperationResult result;
  ModelChange change;
  double ms = 0.0;
};

/// What `Session::finish_edit` did.
struct EditOutcome {
  /// The edited operation as it ran: not `applied()` means nothing changed (still editing).
  OperationEntry edited;
  /// Later operations that no longer apply (or failed) and were skipped.
  std::size_t skipped = 0;
  /// What the current state changed by (structure: the re-run replaces the model).
  ModelChange change;
  double ms = 0.0;
};

/// What `Session::prepare_edit` made: the state after the edited operation and the later ones,
/// not yet current (`Session::commit_edit` makes it so).
struct EditRun {
  EditOutcome outcome;
  std::shared_ptr<Model> result;        ///< null when the edited operation did not apply
  std::vector<OperationEntry> entries;  ///< the operations as they ran
  std::unique_ptr<PosedModel> posed;    ///< describes `result`
};

class Session {
 public:
  /// Whether `apply_history` keeps one undoable state per operation (the studio) or runs the
  /// whole history on one copy and keeps only the result (`deepcut apply`).
  enum class Undo { PerOperation, None };

  explicit Session(Undo undo = Undo::PerOperation) : undo_mode_(undo) {}

  /// Starts anew from `model` (as opened: edited histories re-run from it). Clears the undo
  /// stack, the operations list and the posed model. The session edits its own model: it takes
  /// `model` over when the caller hands it the only reference or `take_over` is set (the studio:
  /// its scene draws that very model, which then changes with every step), else copies it.
  /// Callers reserve room first (`reserve_for_operations`), so the first operations do not
  /// reallocate. The whole model changed (structure) for whoever draws it.
  void open(std::shared_ptr<const Model> model, bool take_over = false);
  /// As `open(model, true)` (taken over: the studio's scene built from it off the UI thread
  /// draws the live model, and no O(mesh) copy is made on the UI thread), with `posed` (built
  /// elsewhere for `model`; nullptr: none) as the posed model.
  void open(std::shared_ptr<const Model> model, std::unique_ptr<PosedModel> posed);

  /// The current state (null before `open`): the live model, edited in place by every
  /// operation, undo and redo (the pointer stays the same; what it points to changes). While
  /// editing a past operation, the state before it (a model of its own). Copy or serialise it
  /// to keep a state.
  const std::shared_ptr<const Model>& current() const { return current_; }

  // --- operations -------------------------------------------------------------------------------
  /// Applies `op` to a copy of the current state. Ok: the copy becomes current (one undo step);
  /// a miss changes nothing. The posed model follows the operation.
  /// @pre not editing. @throws Error (bad parameters; nothing changes) and whatever the
  ///      operation throws (nothing changes).
  Applied apply(const Operation& op);
  /// Sees operation `index` of a history just applied, with the model right after it.
  using AppliedObserver = std::function<void(std::size_t index, const Model& after, const Applied& applied)>;
  /// Runs every operation of `history` on the current state as `deepcut apply` does (one that
  /// misses changes nothing); all first, so a bad operation (or an observer that throws) leaves
  /// the session as it was.
  /// @returns one entry per operation of `history`.
  /// @throws Error naming `source` and the operation index when one is invalid.
  std::vector<Applied> apply_history(const History& history, const std::string& source,
                                     const AppliedObserver& observer = {});
  /// Makes `state` current as one undo step (a change made outside the operations; taken over
  /// when the caller hands the only reference, else copied). The step holds the model it
  /// replaced. @returns the change: structure.
  ModelChange commit(std::shared_ptr<const Model> state);

  /// The operations of the current state since the model was opened: what `deepcut apply` of
  /// them on the opened model reproduces (while editing, the list being edited).
  std::vector<OperationEntry> operations() const;

  // --- editing a past operation -----------------------------------------------------------------
  /// Starts editing operation `index` of `operations()`: the current state becomes the opened
  /// model with the operations before it re-run (not an undo step; a model of its own, so the
  /// whole model changed for whoever draws it). Ends an edit in progress first.
  /// @returns false for a bad index (nothing changes).
  bool begin_edit(int index);
  /// The operation being edited, or -1.
  int editing() const { return editing_.index; }
  /// The operation being edited as it was before the edit. @pre editing() >= 0.
  const OperationEntry& edited_entry() const { return editing_.entries[static_cast<std::size_t>(editing_.index)]; }
  /// Leaves editing: the state before `begin_edit` is current again (the whole model changed).
  void cancel_edit();
  /// Re-runs the edited operation as `op` and then every later one (each that no longer applies
  /// is skipped and marked) as one undo step. When `op` itself misses or fails nothing changes
  /// and the edit goes on. @pre editing() >= 0.
  EditOutcome finish_edit(const Operation& op);
  /// Called before operation `index` of `count` is re-run; it may throw to stop the run (then
  /// nothing changes).
  using RerunObserver = std::function<void(std::size_t index, std::size_t count)>;
  /// The work of `finish_edit` (re-running the edited operation and the later ones on a copy
  /// of the edit's base, with a posed model of its own) without changing the session: it only
  /// reads it (never the live model), so the studio runs it on a worker thread while nothing
  /// else changes the session. O(mesh) for the copy, plus the operations. @pre editing() >= 0.
  EditRun prepare_edit(const Operation& op, const RerunObserver& observer = {}) const;
  /// Makes `run` current as `finish_edit` does: one step that replaces the live model by move
  /// (no copy, so cheap on the UI thread); nothing changes when its edited operation did not
  /// apply. @pre `run` came from `prepare_edit` and the session has not changed since.
  EditOutcome commit_edit(EditRun run);

  // --- undo / redo ------------------------------------------------------------------------------
  /// Number of undo steps, and how many of them are done (the current state is after step
  /// `undo_index() - 1`).
  std::size_t undo_count() const { return steps_.size(); }
  std::size_t undo_index() const { return done_; }
  bool can_undo() const { return done_ > 0; }
  bool can_redo() const { return done_ < steps_.size(); }
  /// Back to the state before the last done step (drops an edit in progress: then the change is
  /// structure, the state shown before was the edit's). @returns what changed (empty: nothing).
  ModelChange undo();
  /// Forward to the state after the next step (drops an edit in progress). @returns what changed.
  ModelChange redo();
  /// Bytes the undo stack holds (what the steps keep of the states not current).
  std::size_t undo_bytes() const;
  /// Bytes the steps that can be undone hold: what an apply keeps (it drops the steps undone), so
  /// `undo_bytes()` after an apply less this before it is what the new step holds.
  std::size_t done_bytes() const;

  // --- the posed model --------------------------------------------------------------------------
  /// The posed model when it describes the current state, else nullptr. Operations keep it up to
  /// date, and it follows a local undo or redo (PosedModel::follow), and a structural undo or
  /// redo (a cut's) whose contents come back as they left in an earlier undo or redo (the
  /// session keeps the posed instances of what a structural step removed: PoseStash), in
  /// O(nodes). `refresh_posed_model` rebuilds it after a cut, a structural undo or redo that
  /// brings back a content not kept so, or a new pose.
  const PosedModel* posed_model() const;
  /// Brings the posed model up to date for the current state at this pose. An error leaves
  /// none (the next operation builds it and reports what is wrong). @returns true when done.
  bool refresh_posed_model(int animation, float time);
  /// The same at a pose with morph weights set by hand (the studio's morph weights panel); the
  /// operations then run at those weights when they carry them (Operation::weights).
  bool refresh_posed_model(const PoseKey& key);
  /// Counts the changes to the state (steps, undo, redo, edits, opens) and to the posed model:
  /// a posed model built elsewhere from the state at one count describes it while the count stays.
  std::uint64_t state_version() const { return version_; }
  /// Takes `posed`, built elsewhere (a front end builds it off its UI thread: once a model it
  /// opened is drawn, after a structural step, after the pose settles) for `built_for` at
  /// `state_version()` `version`, as the posed model when `built_for` is still the live state
  /// unchanged (the same count, not editing). @returns whether it was taken (else `posed` is
  /// dropped). The caller keeps the state unchanged while it is read.
  bool adopt_posed_model(std::unique_ptr<PosedModel> posed, const Model* built_for, std::uint64_t version);
  /// Called before the posed model changes or is replaced (pointers into it, such as grids lent
  /// to a drawn scene, must be dropped).
  void set_posed_model_listener(std::function<void()> before_change) { before_change_ = std::move(before_change); }

 private:
  struct Step {
    ModelStep record;
    /// The operation list of the state after the step when an edit made it (skipped entries
    /// included) or a later step followed such a state; else the model's history gives it.
    std::optional<std::vector<OperationEntry>> entries;
  };
  struct Editing {
    int index = -1;
    std::shared_ptr<Model> base;          // the state before the edited operation
    std::vector<OperationEntry> entries;  // the operations of the live model
  };

  void push(ModelStep record, std::optional<std::vector<OperationEntry>> entries);
  /// The structural step made last and done, past local steps: the last of `pending` (steps
  /// made, not pushed yet) that is, else of the steps done. A new structural step shares the
  /// model's small parts with it (ModelRecorder::finish).
  const ModelStep* last_structural(const std::vector<ModelStep>& pending) const;
  /// Lends `recorder` the memory of the steps undone, which an operation that applies drops
  /// (ModelRecorder::lend_spares): the pieces a cut copies out reuse it instead of new memory.
  void lend_undone(ModelRecorder& recorder);
  /// On every way out of an apply (a miss, a failure, an exception) that pushed no step: the
  /// steps undone are dropped when their memory was taken (they can no longer be redone).
  void drop_lent();
  /// The operation list recorded for the live model by an edit, if any.
  const std::vector<OperationEntry>* rerun_entries() const;
  /// The posed model, made to follow `state` (kept when it describes it, else emptied: the
  /// next operation builds it at its pose). It describes no state until the caller says so.
  PosedModel* posed_for(const Model* state);
  /// Before the state or the posed model changes: counts it, tells the listener.
  void changing();
  /// The posed model follows a step's change to the live model (or is left for a rebuild).
  void follow(const ModelChange& change);
  /// The posed model follows a mapped structural undo or redo when every content it brings
  /// back is in `stash_`; otherwise the instances of what left go into `stash_` and the posed
  /// model is left for a rebuild.
  void follow_structure(const ModelChange& change);
  /// A copy of the model as opened (every done step undone on the live model, copied, redone).
  Model opened_copy();

  Undo undo_mode_;
  std::shared_ptr<Model> live_;
  std::shared_ptr<const Model> current_;  // live_, or the edit's base while editing
  std::size_t opened_operations_ = 0;     // operations already in the opened model's history
  std::vector<Step> steps_;
  std::size_t done_ = 0;
  bool lent_ = false;  // the steps undone gave their memory to an operation (lend_undone)
  Editing editing_;
  // The posed model and the model object it describes as that model is now (nullptr: none).
  std::unique_ptr<PosedModel> posed_;
  const Model* posed_state_ = nullptr;
  // The posed instances (at posed_'s pose) of the contents the last structural undo or redo
  // removed, by (content tag, node): taken back when an undo or redo brings them back.
  PoseStash stash_;
  PoseKey stash_key_;  // the pose stash_ was made at
  std::uint64_t version_ = 0;  // state_version()
  std::function<void()> before_change_;
};

}  // namespace deepcut::session
