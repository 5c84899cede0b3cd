// SPDX-License-Identifier: MIT
#pragma once
/// @file tool_panel.h
/// Numeric entry shared by the tool panels: a row of three spin boxes for a world-space vector.

#include <QString>
#include <functional>
#include <glm/vec3.hpp>

class QDoubleSpinBox;
class QFormLayout;
class QWidget;

namespace deepcut::plugins {

/// A labelled row "x y z" in `form`; its spin boxes are named `name + ".x"` etc. (for tests).
class Vec3Entry {
 public:
  /// @param on_edit  called when the user changes a value (not when `set` is called).
  Vec3Entry(QFormLayout* form, const QString& label, const QString& name, std::function<void()> on_edit);
  glm::vec3 value() const;
  /// Shows `v` without calling `on_edit`.
  void set(const glm::vec3& v);

 private:
  QDoubleSpinBox* spins_[3] = {nullptr, nullptr, nullptr};
};

/// A spin box with a wide range and 4 decimals, named `name`.
QDoubleSpinBox* make_number(QWidget* parent, const QString& name, double min, double max);

}  // namespace deepcut::plugins
