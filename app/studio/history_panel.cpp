// SPDX-License-Identifier: MIT
#include "history_panel.h"

#include <QColor>
#include <QFont>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QPushButton>
#include <QUndoView>
#include <QVBoxLayout>

namespace deepcut::studio {
namespace {

QString vec(const glm::vec3& v) { return QString("(%1, %2, %3)").arg(v.x, 0, 'g', 4).arg(v.y, 0, 'g', 4).arg(v.z, 0, 'g', 4); }

}  // namespace

QString operation_label(const Operation& op) {
  QString text;
  if (const auto* cut = std::get_if<CutOperation>(&op.params))
    text = "Cut  point " + vec(cut->plane.point) + " normal " + vec(cut->plane.normal) +
           (cut->options.cap ? "  cap" : "") + (cut->options.split_components ? "  components" : "") +
           (cut->options.keep == CutKeep::Positive ? "  keep +" : cut->options.keep == CutKeep::Negative ? "  keep -" : "");
  else if (const auto* tear = std::get_if<TearOperation>(&op.params))
    text = "Tear  " + vec(tear->start.tip) + " to " + vec(tear->end.tip) +
           QString("  width %1").arg(tear->options.width, 0, 'g', 4);
  else if (const auto* drill = std::get_if<DrillOperation>(&op.params))
    text = "Drill  " + vec(drill->cylinder.a) + " to " + vec(drill->cylinder.b) +
           QString("  r %1").arg(drill->cylinder.radius, 0, 'g', 4) + (drill->options.wall ? "  wall" : "");
  return text + (op.animation < 0 ? QString("  @ rest") : QString("  @ anim %1 t = %2 s").arg(op.animation).arg(op.time, 0, 'f', 3));
}

HistoryPanel::HistoryPanel(QUndoStack* undo_stack, QWidget* parent) : QWidget(parent) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(4, 4, 4, 4);
  layout->addWidget(new QLabel("Operations (double-click to edit; later ones re-run)", this));
  list_ = new QListWidget(this);
  list_->setObjectName("operations_list");
  layout->addWidget(list_, 1);
  auto* edit_row = new QHBoxLayout();
  edit_button_ = new QPushButton("Edit operation", this);
  edit_button_->setObjectName("edit_operation");
  edit_button_->setEnabled(false);
  cancel_button_ = new QPushButton("Cancel edit", this);
  cancel_button_->setObjectName("cancel_edit");
  cancel_button_->setEnabled(false);
  edit_row->addWidget(edit_button_);
  edit_row->addWidget(cancel_button_);
  layout->addLayout(edit_row);
  connect(list_, &QListWidget::currentRowChanged, this,
          [this](int row) { edit_button_->setEnabled(row >= 0 && editing_ < 0); });
  connect(list_, &QListWidget::itemDoubleClicked, this,
          [this](QListWidgetItem* item) { emit edit_requested(list_->row(item)); });
  connect(edit_button_, &QPushButton::clicked, this, [this] { emit edit_requested(list_->currentRow()); });
  connect(cancel_button_, &QPushButton::clicked, this, &HistoryPanel::cancel_requested);
  layout->addWidget(new QLabel("Undo history (click to go back)", this));
  auto* undo_view = new QUndoView(undo_stack, this);
  undo_view->setEmptyLabel("Opened model");
  layout->addWidget(undo_view, 1);
}

void HistoryPanel::show_operations(const std::vector<session::OperationEntry>& entries, int editing) {
  editing_ = editing;
  const int row = list_->currentRow();
  list_->clear();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const session::OperationEntry& entry = entries[i];
    QString text = QString("%1. %2").arg(i + 1).arg(operation_label(entry.operation));
    auto* item = new QListWidgetItem(list_);
    if (!entry.applied()) {
      const QString why = entry.error.empty() ? QString("no longer applies (%1)").arg(to_string(entry.status))
                                              : QString("failed: %1").arg(QString::fromStdString(entry.error));
      text = QString::fromUtf8("✗ ") + text + "  - " + why + ", skipped";
      item->setForeground(QColor(255, 120, 110));
      item->setToolTip("After the last edit this operation " + why + "; it was skipped. Edit it to fix it.");
    }
    if (static_cast<int>(i) == editing) {
      QFont font = item->font();
      font.setBold(true);
      item->setFont(font);
      text = QString::fromUtf8("✎ ") + text;
    }
    item->setText(text);
  }
  if (row >= 0 && row < list_->count()) list_->setCurrentRow(row);
  edit_button_->setEnabled(editing < 0 && list_->currentRow() >= 0);
  cancel_button_->setEnabled(editing >= 0);
}

}  // namespace deepcut::studio
