// SPDX-License-Identifier: MIT
#include "deepcut/plugins/tool_panel.h"

#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QSignalBlocker>
#include <QWidget>

namespace deepcut::plugins {

QDoubleSpinBox* make_number(QWidget* parent, const QString& name, double min, double max) {
  auto* spin = new QDoubleSpinBox(parent);
  spin->setObjectName(name);
  spin->setRange(min, max);
  spin->setDecimals(4);
  spin->setSingleStep(0.01);
  spin->setKeyboardTracking(false);
  return spin;
}

Vec3Entry::Vec3Entry(QFormLayout* form, const QString& label, const QString& name, std::function<void()> on_edit) {
  auto* row = new QWidget(form->parentWidget());
  auto* layout = new QHBoxLayout(row);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->setSpacing(2);
  const char* axes[3] = {".x", ".y", ".z"};
  for (int k = 0; k < 3; ++k) {
    spins_[k] = make_number(row, name + axes[k], -1e6, 1e6);
    layout->addWidget(spins_[k]);
    QObject::connect(spins_[k], QOverload<double>::of(&QDoubleSpinBox::valueChanged), row,
                     [on_edit](double) { on_edit(); });
  }
  form->addRow(label, row);
}

glm::vec3 Vec3Entry::value() const {
  return {static_cast<float>(spins_[0]->value()), static_cast<float>(spins_[1]->value()),
          static_cast<float>(spins_[2]->value())};
}

void Vec3Entry::set(const glm::vec3& v) {
  for (int k = 0; k < 3; ++k) {
    const QSignalBlocker block(spins_[k]);
    spins_[k]->setValue(static_cast<double>(v[k]));
  }
}

}  // namespace deepcut::plugins
