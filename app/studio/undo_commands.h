// SPDX-License-Identifier: MIT
#pragma once
/// @file undo_commands.h
/// The studio's undo stack over the Session's (app/session/session.h): one QUndoCommand per
/// session step, so the History panel, QUndoView and the Edit menu drive the session's undo and
/// redo.

#include <QUndoCommand>
#include <functional>

#include "session.h"

namespace deepcut::studio {

/// The step the session has just made (its state is current when this is pushed; `made` is
/// what it changed): undo and redo move the session's stack, then `show` draws the session's
/// current state, told what the move changed.
class SessionStepCommand : public QUndoCommand {
 public:
  SessionStepCommand(session::Session& session, const QString& label, ModelChange made,
                     std::function<void(const ModelChange&)> show)
      : QUndoCommand(label), session_(session), made_(std::move(made)), show_(std::move(show)) {}
  /// Runs before each undo and redo moves the session (not before the first redo: the step is
  /// already made).
  void set_before_step(std::function<void()> settle) { before_step_ = std::move(settle); }
  void undo() override;
  void redo() override;

 private:
  session::Session& session_;
  ModelChange made_;  // shown by the first redo, then dropped
  std::function<void(const ModelChange&)> show_;
  std::function<void()> before_step_;
  bool pushed_ = false;  // the first redo (QUndoStack::push) finds the step already made
};

}  // namespace deepcut::studio
