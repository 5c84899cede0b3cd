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
/// Model states are immutable snapshots (`std::shared_ptr<const Model>`): an operation copies the
/// current state, edits the copy and makes it current, so undo and redo give back the very
/// states they left, byte for byte.

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "deepcut/core/model.h"
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

/// What `Session::apply` did: the operation's result and how long it took.
struct Applied {
  OperationResult result;
  double ms = 0.0;
};

/// What `Session::finish_edit` did.
struct EditOutcome {
  /// The edited operation as it ran: not `applied()` means nothing changed (still editing).
  OperationEntry edited;
  /// Later operations that no longer apply (or failed) and were skipped.
  std::size_t skipped = 0;
  double ms = 0.0;
};

/// What `Session::prepare_edit` made: the state after the edited operation and the later ones,
/// not yet current (`Session::commit_edit` makes it so).
struct EditRun {
  EditOutcome outcome;
  std::shared_ptr<const Model> result;  ///< null when the edited operation did not apply
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
  /// stack, the operations list and the posed model. Callers reserve room first
  /// (`reserve_for_operations`), so every snapshot copied from it keeps that room.
  void open(std::shared_ptr<const Model> model);
  /// As `open`, with `posed` (built elsewhere for `model`, e.g. off the studio's UI thread;
  /// nullptr: none) as the posed model.
  void open(std::shared_ptr<const Model> model, std::unique_ptr<PosedModel> posed);

  /// The current state (null before `open`).
  const std::shared_ptr<const Model>& current() const { return current_; }
  /// The state as opened.
  const std::shared_ptr<const Model>& original() const { return original_; }

  // --- operations -------------------------------------------------------------------------------
  /// Applies `op` to a copy of the current state. Ok: the copy becomes current (one undo step);
  /// a miss changes nothing. The posed model follows the operation.
  /// @pre not editing. @throws Error (bad parameters; nothing changes) and whatever the
  ///      operation throws (nothing changes).
  Applied apply(const Operation& op);
  /// Sees operation `index` of a history just applied, with the model right after it.
  using AppliedObserver = std::function<void(std::size_t index, const Model& after, const Applied& applied)>;
  /// Runs every operation of `history` on the current state as `deepcut apply` does (one that
  /// misses changes nothing); all first, so a bad operation leaves the session as it was.
  /// @returns one entry per operation of `history`.
  /// @throws Error naming `source` and the operation index when one is invalid.
  std::vector<Applied> apply_history(const History& history, const std::string& source,
                                     const AppliedObserver& observer = {});
  /// Makes `state` current as one undo step (a change made outside the operations).
  void commit(std::shared_ptr<const Model> state);

  /// The operations of the current state since the model was opened: what `deepcut apply` of
  /// them on the opened model reproduces (while editing, the list being edited).
  std::vector<OperationEntry> operations() const;

  // --- editing a past operation -----------------------------------------------------------------
  /// Starts editing operation `index` of `operations()`: the current state becomes the opened
  /// model with the operations before it re-run (not an undo step). Ends an edit in progress
  /// first. @returns false for a bad index (nothing changes).
  bool begin_edit(int index);
  /// The operation being edited, or -1.
  int editing() const { return editing_.index; }
  /// The operation being edited as it was before the edit. @pre editing() >= 0.
  const OperationEntry& edited_entry() const { return editing_.entries[static_cast<std::size_t>(editing_.index)]; }
  /// Leaves editing: the state before `begin_edit` is current again.
  void cancel_edit();
  /// Re-runs the edited operation as `op` and then every later one (each that no longer applies
  /// is skipped and marked) as one undo step. When `op` itself misses or fails nothing changes
  /// and the edit goes on. @pre editing() >= 0.
  EditOutcome finish_edit(const Operation& op);
  /// Called before operation `index` of `count` is re-run; it may throw to stop the run (then
  /// nothing changes).
  using RerunObserver = std::function<void(std::size_t index, std::size_t count)>;
  /// The work of `finish_edit` (re-running the edited operation and the later ones on a copy)
  /// without changing the session: it only reads it, so the studio runs it on a worker thread
  /// while nothing else changes the session, with its own posed model. @pre editing() >= 0.
  EditRun prepare_edit(const Operation& op, const RerunObserver& observer = {}) const;
  /// Makes `run` current as `finish_edit` does (nothing changes when its edited operation did
  /// not apply). @pre `run` came from `prepare_edit` and the session has not changed since.
  EditOutcome commit_edit(EditRun run);

  // --- undo / redo ------------------------------------------------------------------------------
  /// Number of undo steps, and how many of them are done (the current state is after step
  /// `undo_index() - 1`).
  std::size_t undo_count() const { return steps_.size(); }
  std::size_t undo_index() const { return done_; }
  bool can_undo() const { return done_ > 0; }
  bool can_redo() const { return done_ < steps_.size(); }
  /// Back to the state before the last done step (drops an edit in progress).
  void undo();
  /// Forward to the state after the next step (drops an edit in progress).
  void redo();

  // --- the posed model --------------------------------------------------------------------------
  /// The posed model when it describes the current state, else nullptr. Operations keep it up to
  /// date; `refresh_posed_model` rebuilds it after undo, redo, a cut or a new pose.
  const PosedModel* posed_model() const;
  /// Brings the posed model up to date for the current state at this pose. An error leaves
  /// none (the next operation builds it and reports what is wrong). @returns true when done.
  bool refresh_posed_model(int animation, float time);
  /// The same at a pose with morph weights set by hand (the studio's morph weights panel); the
  /// operations then run at those weights when they carry them (Operation::weights).
  bool refresh_posed_model(const PoseKey& key);
  /// Called before the posed model changes or is replaced (pointers into it, such as grids lent
  /// to a drawn scene, must be dropped).
  void set_posed_model_listener(std::function<void()> before_change) { before_change_ = std::move(before_change); }

 private:
  struct Step {
    std::shared_ptr<const Model> before, after;
  };
  struct Editing {
    int index = -1;
    std::shared_ptr<const Model> current;  // the state to return to
    std::vector<OperationEntry> entries;   // its operations
  };

  void push(std::shared_ptr<const Model> after);
  /// The posed model, made to follow `state` (kept when it describes it, else emptied: the
  /// next operation builds it at its pose). It describes no state until the caller says so.
  PosedModel* posed_for(const std::shared_ptr<const Model>& state);
  /// The re-run list recorded for `model` by an edit, if any.
  const std::vector<OperationEntry>* rerun_entries(const Model* model) const;

  Undo undo_mode_;
  std::shared_ptr<const Model> current_, original_;
  std::size_t opened_operations_ = 0;  // operations already in the opened model's history
  std::vector<Step> steps_;
  std::size_t done_ = 0;
  // Operation lists of states made by an edit (skipped entries included), by state.
  std::vector<std::pair<std::weak_ptr<const Model>, std::vector<OperationEntry>>> reruns_;
  Editing editing_;
  // The posed model and the state it describes (operations run on a copy of the current state:
  // the posed model follows them and then describes the copy).
  std::unique_ptr<PosedModel> posed_;
  std::weak_ptr<const Model> posed_state_;
  std::function<void()> before_change_;
};

}  // namespace deepcut::session
