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

/// The step the session has just made (its state is current when this is pushed): undo and
/// redo move the session's stack, then `show` draws the session's current state.
class SessionStepCommand : public QUndoCommand {
 public:
  SessionStepCommand(session::Session& session, const QString& label, std::function<void()> show)
      : QUndoCommand(label), session_(session), show_(std::move(show)) {}
  void undo() override;
  void redo() override;

 private:
  session::Session& session_;
  std::function<void()> show_;
  bool pushed_ = false;  // the first redo (QUndoStack::push) finds the step already made
};

}  // namespace deepcut::studio
