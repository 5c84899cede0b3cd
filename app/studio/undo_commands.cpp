// SPDX-License-Identifier: MIT
#include "undo_commands.h"

namespace deepcut::studio {

void SessionStepCommand::undo() {
  session_.undo();
  show_();
}

void SessionStepCommand::redo() {
  if (pushed_) session_.redo();
  pushed_ = true;
  show_();
}

}  // namespace deepcut::studio
