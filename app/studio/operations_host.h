// SPDX-License-Identifier: MIT
#pragma once
/// @file operations_host.h
/// The studio's side of the Session (app/session/session.h): applies the active tool's operation
/// or a whole history at the shown pose, edits a past operation and re-runs the later ones,
/// mirrors the session's steps on the undo stack (undo_commands.h) and lists the operations in
/// the History panel (history_panel.h). The window shows the states it makes and reports what
/// it says. See docs/studio.md.

#include <QObject>
#include <QString>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "deepcut/core/ops/operation.h"
#include "session.h"

class QListWidget;
class QUndoStack;
class QWidget;

namespace deepcut::studio {

class BackgroundTask;
class HistoryPanel;
class ToolHost;

class OperationsHost : public QObject {
  Q_OBJECT

 public:
  /// Operations take their parameters from `tools` and their pose from its scene.
  OperationsHost(ToolHost* tools, QObject* parent);

  session::Session& session() { return session_; }
  const session::Session& session() const { return session_; }
  QUndoStack* undo_stack() const { return undo_stack_; }
  /// The History panel (operations list over the undo stack).
  QWidget* create_panel(QWidget* parent);
  QListWidget* operations_list() const;

  /// Starts anew from `model` (no undo steps, no operations), with `posed` built for it (or
  /// nullptr). The session takes it over and edits it in place: whoever holds it (the scene)
  /// sees every step.
  void open(std::shared_ptr<const Model> model, std::unique_ptr<PosedModel> posed = nullptr);
  /// Re-runs of an edited history go through `task` (off the UI thread, with progress and
  /// Cancel); without one they run at once.
  void set_task(BackgroundTask* task) { task_ = task; }
  /// Runs before each undo or redo moves the session (the studio waits there for a worker that
  /// reads the model).
  void set_before_step(std::function<void()> settle) { before_step_ = std::move(settle); }
  /// See MainWindow::apply_tool (the caller clears its last error on success). While editing,
  /// the re-run starts off the UI thread: true means it started, and `edit_applied()` says, once
  /// the task has ended, whether it made the new state.
  bool apply_tool();
  bool edit_applied() const { return edit_applied_; }
  /// See MainWindow::apply_history. @throws Error naming `source` and the operation.
  void apply_history(const History& history, const std::string& source);
  /// `state` becomes current as one undo step named `label`.
  void commit(const QString& label, std::shared_ptr<const Model> state, double ms);
  /// See MainWindow::edit_operation.
  bool edit_operation(int index);
  void cancel_edit();
  /// What the last step shown changed (an operation, undo or redo: what `state_changed` was
  /// emitted for), then forgotten: structure (show everything again) when no step says.
  ModelChange take_change();
  /// Lists the session's operations (and the edit in progress) in the History panel and the
  /// tool panel's banner.
  void refresh_list();

 signals:
  /// The session's current state changed: show it.
  void state_changed();
  /// An operation (or an edit) could not be applied: report `message`.
  void failed(const QString& message);
  /// `label` was done in `ms` (the status bar's last operation).
  void done(const QString& label, double ms);
  /// A passing note for the status bar.
  void note(const QString& text, int timeout_ms);
  /// Editing an operation poses the model as the operation was placed.
  void pose_requested(int animation, float time);
  /// A miss changed nothing: the posed model still describes the shown state.
  void state_kept();

 private:
  /// Pushes the session's newest step on the undo stack, named `label`; `change` is what it
  /// changed.
  void push_step(const QString& label, const ModelChange& change);
  /// Before `op` is applied: a cut needs the model posed, not its grids. When the session has no
  /// posed model at the cut's pose (a cut, its undo or redo left none, or the time line or the
  /// morph weights moved, and the idle rebuild has not run yet), it is lent a copy of the scene's
  /// (PosedModel::positions_copy), which describes the live model at the shown pose (the scene
  /// follows every step), instead of the cut posing the model again.
  void lend_scene_pose(const Operation& op);
  /// Re-runs the edited operation with the tool's parameters and every later one.
  bool apply_edit();
  /// Reports what a re-run made (on the UI thread) and makes it current. @returns true when
  /// the edited operation applied.
  bool take_edit(session::EditRun run, const std::string& title, int index);
  /// After an apply that did not apply but dropped the session's undone steps (their memory was
  /// taken: Session::apply): drops the undo stack's redo commands too, so that Undo and Redo keep
  /// acting on the session's steps.
  void drop_stale_redo();
  /// Reports what `run` throws (an operation's defect included) as `title: ...`, then drops the
  /// redo commands the session no longer has (drop_stale_redo).
  template <class Run>
  bool reporting(const std::string& title, Run&& run);

  ToolHost* tools_;
  session::Session session_;
  ModelChange last_change_{true, {}};  // see take_change
  QUndoStack* undo_stack_ = nullptr;
  HistoryPanel* panel_ = nullptr;
  BackgroundTask* task_ = nullptr;
  std::function<void()> before_step_;  // set_before_step
  bool edit_applied_ = false;
};

}  // namespace deepcut::studio
