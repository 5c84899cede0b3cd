// SPDX-License-Identifier: MIT
#pragma once
/// @file widget_tool.h
/// The shared shape of an operation tool driven by an interactive VTK widget (Plane, Scalpel,
/// Drill). The tool owns one parameter struct `Op` and keeps its three views in step:
/// - a drag of the widget reads the widget into the parameters and shows them in the panel;
/// - a typed number, a panel button, `place` or `set_parameters` writes the widget;
/// - showing a value is never an edit (spin boxes are set with their signals blocked), so
///   nothing loops; every change calls the changed callback (the studio redraws the preview).
/// A tool derives from `WidgetTool<Op, Widget>` and supplies `read_widget`, `write_widget` and
/// `show_panel`; it calls `write_widget()` at the end of its constructor.

#include <vtkCommand.h>
#include <vtkSmartPointer.h>

#include <QString>
#include <optional>
#include <variant>

#include "deepcut/core/errors.h"
#include "deepcut/plugins/tool.h"
#include "deepcut/plugins/tool_panel.h"

class QFormLayout;

namespace deepcut::plugins {

template <class Op, class Widget>
class WidgetTool : public Tool {
 public:
  WidgetTool() {
    widget_ = vtkSmartPointer<Widget>::New();
    widget_->CreateDefaultRepresentation();
    widget_->AddObserver(vtkCommand::InteractionEvent, this, &WidgetTool::on_widget_moved);
  }
  ~WidgetTool() override {
    widget_->RemoveAllObservers();
    widget_->Off();
  }
  WidgetTool(const WidgetTool&) = delete;
  WidgetTool& operator=(const WidgetTool&) = delete;

  vtkAbstractWidget* widget() override { return widget_; }

  OperationParams parameters() const override { return op_; }

  /// @throws Error{InvalidArgument} ("the Plane tool takes cut parameters") for another type.
  void set_parameters(const OperationParams& params) override {
    const auto* op = std::get_if<Op>(&params);
    if (!op) throw Error(ErrorCode::InvalidArgument, "the " + title() + " tool takes " + id() + " parameters");
    op_ = *op;
    refresh();
  }

 protected:
  /// The widget's state becomes the parameters (after a drag).
  virtual void read_widget() = 0;
  /// The parameters move the widget (no interaction event follows).
  virtual void write_widget() = 0;
  /// The parameters are shown in the panel without edit signals (nothing before create_panel).
  virtual void show_panel() = 0;

  /// The parameters changed in code: panel, widget and the changed callback follow.
  void refresh() {
    show_panel();
    write_widget();
    notify_changed();
  }

  /// A panel row "x y z" editing `field`, a vector inside op_: typing moves the widget.
  void add_vec3_row(std::optional<Vec3Entry>& entry, QFormLayout* form, const QString& label, const QString& name,
                    glm::vec3& field) {
    entry.emplace(form, label, name, [this, &entry, &field] {
      field = entry->value();
      write_widget();
      notify_changed();
    });
  }

  Op op_;
  vtkSmartPointer<Widget> widget_;

 private:
  void on_widget_moved() {
    read_widget();
    show_panel();
    notify_changed();
  }
};

}  // namespace deepcut::plugins
