// SPDX-License-Identifier: MIT
#pragma once
/// @file history_panel.h
/// The History dock: the operations of the current state (select one and edit it: the later ones
/// re-run), above the undo stack (click an entry to go back). See docs/studio.md.

#include <QString>
#include <QWidget>
#include <vector>

#include "deepcut/core/ops/operation.h"
#include "session.h"

class QListWidget;
class QPushButton;
class QUndoStack;

namespace deepcut::studio {

/// An operation as the history lists it: type, main parameters and the pose time.
QString operation_label(const Operation& op);

class HistoryPanel : public QWidget {
  Q_OBJECT

 public:
  HistoryPanel(QUndoStack* undo_stack, QWidget* parent);

  QListWidget* operations_list() const { return list_; }
  /// Lists `entries` (skipped ones marked), `editing` (-1: none) in bold, keeping the selection.
  void show_operations(const std::vector<session::OperationEntry>& entries, int editing);

 signals:
  /// Edit operation `row` (the Edit button or a double click).
  void edit_requested(int row);
  void cancel_requested();

 private:
  QListWidget* list_ = nullptr;
  QPushButton* edit_button_ = nullptr;
  QPushButton* cancel_button_ = nullptr;
  int editing_ = -1;
};

}  // namespace deepcut::studio
