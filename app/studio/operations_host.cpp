// SPDX-License-Identifier: MIT
#include "operations_host.h"

#include <QElapsedTimer>
#include <QListWidget>
#include <QUndoStack>
#include <memory>
#include <new>
#include <variant>

#include "background_task.h"
#include "deepcut/plugins/scene.h"
#include "deepcut/core/errors.h"
#include "history_panel.h"
#include "tool_host.h"
#include "undo_commands.h"

namespace deepcut::studio {
namespace {

std::string tool_of(const Operation& op) {
  if (std::holds_alternative<CutOperation>(op.params)) return "cut";
  if (std::holds_alternative<TearOperation>(op.params)) return "tear";
  return "drill";
}

/// The active tool's parameters at the scene's pose.
Operation tool_operation(const ToolHost& tools) {
  Operation op;
  op.params = tools.tool()->parameters();
  op.animation = tools.scene()->animation;
  op.time = tools.scene()->time;
  op.weights = tools.scene()->weights;  // the morph weights set by hand, as drawn
  return op;
}

}  // namespace

void OperationsHost::lend_scene_pose(const Operation& op) {
  const plugins::Scene* scene = tools_->scene();
  const PoseKey key(op.animation, op.time, op.weights);
  // A posed model at another pose (the time line or the morph weights moved, and the idle
  // rebuild has not run yet) is no use to the cut: it would pose the whole model again on its own.
  const PosedModel* posed = session_.posed_model();
  if (!std::holds_alternative<CutOperation>(op.params) || (posed && posed->matches(key)) ||
      session_.editing() >= 0 || !scene || !scene->posed || scene->model != session_.current() ||
      !scene->posed->matches(key))
    return;
  session_.adopt_posed_model(std::make_unique<PosedModel>(scene->posed->positions_copy()), session_.current().get(),
                             session_.state_version());
}

OperationsHost::OperationsHost(ToolHost* tools, QObject* parent) : QObject(parent), tools_(tools) {
  undo_stack_ = new QUndoStack(this);
}

QWidget* OperationsHost::create_panel(QWidget* parent) {
  panel_ = new HistoryPanel(undo_stack_, parent);
  connect(panel_, &HistoryPanel::edit_requested, this, &OperationsHost::edit_operation);
  connect(panel_, &HistoryPanel::cancel_requested, this, &OperationsHost::cancel_edit);
  return panel_;
}

QListWidget* OperationsHost::operations_list() const { return panel_->operations_list(); }

void OperationsHost::open(std::shared_ptr<const Model> model, std::unique_ptr<PosedModel> posed) {
  undo_stack_->clear();
  session_.open(std::move(model), std::move(posed));  // taken over: the scene draws the session's live model
}

void OperationsHost::push_step(const QString& label, const ModelChange& change) {
  auto* command = new SessionStepCommand(session_, label, change, [this](const ModelChange& c) {
    last_change_ = c;
    emit state_changed();
  });
  command->set_before_step(before_step_);
  undo_stack_->push(command);
}

ModelChange OperationsHost::take_change() {
  ModelChange change = std::move(last_change_);
  last_change_ = ModelChange();
  last_change_.structure = true;
  return change;
}

void OperationsHost::commit(const QString& label, std::shared_ptr<const Model> state, double ms) {
  if (!session_.current() || !state) return;
  push_step(label, session_.commit(std::move(state)));
  emit done(label, ms);
}

void OperationsHost::drop_stale_redo() {
  if (session_.can_redo() || !undo_stack_->canRedo()) return;
  auto* drop = new QUndoCommand;
  drop->setObsolete(true);  // never run nor kept: pushing it drops the commands past the index
  undo_stack_->push(drop);
}

template <class Run>
bool OperationsHost::reporting(const std::string& title, Run&& run) {
  bool ran = false;
  try {
    run();
    ran = true;
  } catch (const Error& e) {
    emit failed(QString::fromStdString(title + ": " + e.what()));
  } catch (const std::bad_alloc&) {
    emit failed(QString::fromStdString(title) + ": out of memory");
  } catch (const std::exception& e) {  // a defect in an operation: reported, never a crash
    emit failed(QString::fromStdString(title + ": internal error: " + e.what()));
  }
  drop_stale_redo();
  return ran;
}

bool OperationsHost::apply_tool() {
  plugins::Tool* tool = tools_->tool();
  if (!session_.current() || !tools_->scene()) {
    emit failed("apply: no model is open");
    return false;
  }
  if (!tool || !tool->makes_operation()) {
    emit failed("apply: no operation tool is chosen (Tools: Plane, Scalpel or Drill)");
    return false;
  }
  if (session_.editing() >= 0) return apply_edit();
  const Operation op = tool_operation(*tools_);
  lend_scene_pose(op);
  session::Applied applied;
  if (!reporting(tool->title(), [&] { applied = session_.apply(op); })) return false;
  if (applied.result.status != OpStatus::Ok) {
    emit state_kept();
    emit failed(QString::fromStdString(tool->title()) + ": the tool misses the model (nothing changed)");
    return false;
  }
  push_step(operation_label(op), applied.change);
  emit done(operation_label(op), applied.ms);
  return true;
}

void OperationsHost::apply_history(const History& history, const std::string& source) {
  if (!history.operations.empty()) lend_scene_pose(history.operations.front());
  std::vector<session::Applied> applied;
  try {
    applied = session_.apply_history(history, source);
  } catch (...) {
    drop_stale_redo();
    throw;
  }
  ModelChange structure;
  structure.structure = true;
  for (std::size_t i = 0; i < applied.size(); ++i)
    if (applied[i].result.status == OpStatus::Ok) {
      // Every operation ran before the first step is shown: one step alone says what changed.
      push_step(operation_label(history.operations[i]), applied.size() == 1 ? applied[i].change : structure);
      emit done(operation_label(history.operations[i]), applied[i].ms);
    }
}

void OperationsHost::refresh_list() {
  const std::vector<session::OperationEntry> entries = session_.operations();
  const int editing = session_.editing();
  panel_->show_operations(entries, editing);
  if (editing < 0) return tools_->set_banner(QString(), "Apply (Enter)");
  tools_->set_banner(QString("Editing operation %1 of %2 (the model as it was before it). Apply re-runs "
                             "it and the %3 after it as one undoable step; Esc cancels.")
                         .arg(editing + 1)
                         .arg(entries.size())
                         .arg(static_cast<int>(entries.size()) - editing - 1),
                     "Re-run from here (Enter)");
}

bool OperationsHost::edit_operation(int index) {
  if (session_.editing() >= 0) cancel_edit();
  QElapsedTimer clock;
  clock.start();
  bool started = false;
  try {
    started = session_.begin_edit(index);
  } catch (const std::bad_alloc&) {
    emit failed("edit: out of memory");
    return false;
  }
  if (!started) {
    emit failed(QString("edit: there is no operation %1 to edit").arg(index + 1));
    return false;
  }
  const Operation edited = session_.edited_entry().operation;
  emit state_changed();
  // Its tool with its parameters, at its pose.
  if (edited.animation < static_cast<int>(session_.current()->animations.size()))
    emit pose_requested(edited.animation, edited.time);
  tools_->set_tool(tool_of(edited));
  tools_->tool()->set_parameters(edited.params);
  refresh_list();
  operations_list()->setCurrentRow(index);
  emit done(QString("Edit operation %1").arg(index + 1), static_cast<double>(clock.nsecsElapsed()) / 1e6);
  return true;
}

void OperationsHost::cancel_edit() {
  if (session_.editing() < 0) return;
  session_.cancel_edit();
  emit state_changed();
  emit note("Edit cancelled: the history is unchanged", 5000);
}

bool OperationsHost::apply_edit() {
  const std::string title = tools_->tool()->title();
  const int index = session_.editing();
  Operation op = session_.edited_entry().operation;
  const Operation placed = tool_operation(*tools_);
  op.params = placed.params;
  op.animation = placed.animation;
  op.time = placed.time;
  op.weights = placed.weights;
  edit_applied_ = false;
  if (!task_) {
    try {
      return take_edit(session_.prepare_edit(op), title, index);
    } catch (const std::bad_alloc&) {
      emit failed(QString::fromStdString(title) + ": out of memory");
      return false;
    }
  }
  // Off the UI thread: the session is only read (edits are disabled while the task runs), the
  // new state becomes current in the Deliver; Cancel leaves the edit as it was.
  BackgroundTask::Job job = [this, op, title, index](TaskProgress& progress) -> BackgroundTask::Deliver {
    auto run = std::make_shared<session::EditRun>(session_.prepare_edit(op, [&](std::size_t i, std::size_t count) {
      progress.stage(QString("operation %1 of %2").arg(i + 1).arg(count));
    }));
    progress.stage("Drawing");
    return [this, run, title, index] { take_edit(std::move(*run), title, index); };
  };
  return task_->start(
      QString("Re-running from operation %1").arg(index + 1), static_cast<int>(session_.operations().size()) - index + 1,
      std::move(job),
      [this, title](std::exception_ptr error) {
        try {
          std::rethrow_exception(error);
        } catch (const std::bad_alloc&) {
          emit failed(QString::fromStdString(title) + ": out of memory");
        } catch (const std::exception& e) {
          emit failed(QString::fromStdString(title + ": internal error: " + e.what()));
        }
      },
      [this] {
        emit note("Re-run cancelled: the history is unchanged", 5000);
      });
}

bool OperationsHost::take_edit(session::EditRun run, const std::string& title, int index) {
  const session::EditOutcome outcome = session_.commit_edit(std::move(run));
  if (!outcome.edited.error.empty()) {
    emit state_kept();
    emit failed(QString::fromStdString(title + ": " + outcome.edited.error));
    return false;
  }
  if (outcome.edited.status != OpStatus::Ok) {
    emit state_kept();
    emit failed(QString::fromStdString(title) + ": the edited operation misses the model (nothing changed)");
    return false;
  }
  edit_applied_ = true;
  const QString label = QString("Edit %1: %2").arg(index + 1).arg(operation_label(outcome.edited.operation));
  push_step(label, outcome.change);
  emit done(label, outcome.ms);
  operations_list()->setCurrentRow(index);
  const std::size_t skipped = outcome.skipped;
  if (skipped > 0)
    emit note(QString("%1 later operation%2 no longer appl%3 and %4 skipped (marked in History)")
                  .arg(skipped)
                  .arg(skipped == 1 ? "" : "s")
                  .arg(skipped == 1 ? "ies" : "y")
                  .arg(skipped == 1 ? "was" : "were"),
              15000);
  return true;
}

}  // namespace deepcut::studio
