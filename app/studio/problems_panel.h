// SPDX-License-Identifier: MIT
#pragma once
/// @file problems_panel.h
/// The Problems panel: what reading the open model repaired or dropped (`Model::import_problems`),
/// one row per kind with its count and places, as `deepcut` prints them on stderr. The main window
/// shows it when a model with problems opens, points at it from the status bar, and asks before
/// exporting such a model, so nothing the reader changed goes unseen.

#include <QString>
#include <QStringList>
#include <QWidget>
#include <vector>

#include "deepcut/core/model.h"

class QLabel;
class QListWidget;

namespace deepcut::studio {

class ProblemsPanel : public QWidget {
  Q_OBJECT

 public:
  explicit ProblemsPanel(QWidget* parent = nullptr);

  /// Lists the problems of the model read from `file` (its name, for the header and messages);
  /// an empty list clears the panel.
  void set_problems(const QString& file, const std::vector<ImportProblem>& problems);
  /// The rows as shown: "MESSAGE [KIND]", one per kind.
  QStringList lines() const { return lines_; }
  /// The status-bar note pointing at the panel ("" when there is nothing to say).
  QString summary() const;
  /// What the export asks before writing ("" when the model had no problems): the file, the
  /// rows, and that the export writes the repaired model.
  QString export_question() const;

 private:
  QString file_;
  QStringList lines_;
  QLabel* header_ = nullptr;
  QListWidget* list_ = nullptr;
};

}  // namespace deepcut::studio
