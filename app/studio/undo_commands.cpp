// SPDX-License-Identifier: MIT
#include "undo_commands.h"

namespace deepcut::studio {

void SessionStepCommand::undo() {
  if (before_step_) before_step_();
  show_(session_.undo());
}

void SessionStepCommand::redo() {
  if (pushed_) {
    if (before_step_) before_step_();
    return show_(session_.redo());
  }
  pushed_ = true;
  show_(made_);
  made_ = ModelChange();
}

}  // namespace deepcut::studio
