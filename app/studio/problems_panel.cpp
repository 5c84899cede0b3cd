// SPDX-License-Identifier: MIT
#include "problems_panel.h"

#include <QLabel>
#include <QListWidget>
#include <QVBoxLayout>

namespace deepcut::studio {

ProblemsPanel::ProblemsPanel(QWidget* parent) : QWidget(parent) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(4, 4, 4, 4);
  header_ = new QLabel("No model with problems is open.", this);
  header_->setObjectName("problems_header");
  header_->setWordWrap(true);
  list_ = new QListWidget(this);
  list_->setObjectName("problems_list");
  list_->setWordWrap(true);
  list_->setSelectionMode(QAbstractItemView::NoSelection);
  layout->addWidget(header_);
  layout->addWidget(list_);
}

void ProblemsPanel::set_problems(const QString& file, const std::vector<ImportProblem>& problems) {
  file_ = file;
  lines_.clear();
  list_->clear();
  for (const auto& p : problems) {
    const QString line = QString::fromStdString(p.message) + " [" + QString::fromStdString(p.kind) + "]";
    lines_ << line;
    auto* item = new QListWidgetItem(line, list_);
    QStringList places;
    for (const auto& place : p.places) places << QString::fromStdString(place);
    item->setToolTip(QString::fromStdString(p.kind) + (places.isEmpty() ? QString() : "\n" + places.join("\n")));
  }
  header_->setText(lines_.isEmpty() ? "Reading " + file + " repaired and dropped nothing."
                                    : "Reading " + file + " repaired or dropped (the model shown and exported "
                                                          "is the repaired one):");
}

QString ProblemsPanel::summary() const {
  if (lines_.isEmpty()) return QString();
  const QString kinds = lines_.size() == 1 ? "1 kind" : QString::number(lines_.size()) + " kinds";
  return file_ + ": " + kinds + " of repair or loss on reading; see the Problems panel";
}

QString ProblemsPanel::export_question() const {
  if (lines_.isEmpty()) return QString();
  return "Reading " + file_ + " repaired or dropped:\n\n- " + lines_.join("\n- ") +
         "\n\nThe export writes the repaired model. Export anyway?";
}

}  // namespace deepcut::studio
