// SPDX-License-Identifier: MIT
#pragma once
/// @file tool_widget.h
/// Shared base of the scalpel and drill widgets (VTK naming): the event handling of a widget
/// whose representation (a ToolRepresentation) is a set of parts dragged in the view plane.
/// Include only in .cpp files: it pulls in VTK.
///
/// @par Event Bindings:
/// The widget watches the vtkRenderWindowInteractor for these VTK events:
/// <pre>
///   MouseMoveEvent (no button)   - highlight the part under the cursor (hand cursor)
///   LeftButtonPressEvent         - over a part: select it (StartInteractionEvent)
///   MouseMoveEvent (dragging)    - move the selected part in the view plane (InteractionEvent)
///   LeftButtonReleaseEvent       - release it (EndInteractionEvent)
///   MiddleButtonPressEvent       - over any part: select the whole tool
///   MiddleButtonReleaseEvent     - release it
///   KeyPressEvent Escape         - while dragging: put the tool back where the drag started
///                                  (InteractionEvent, then EndInteractionEvent)
/// </pre>
/// Events over no part pass on to the interactor style (the camera). The vtkWidgetEventTranslator
/// maps them to vtkWidgetEvent::Select, EndSelect, Translate, EndTranslate, Move and Reset,
/// handled by SelectAction, EndSelectAction, TranslateAction, MoveAction and CancelAction.

#include <vtkAbstractWidget.h>

namespace deepcut {

class ToolWidget : public vtkAbstractWidget {
 public:
  vtkTypeMacro(ToolWidget, vtkAbstractWidget)

  /// True while a part is being dragged.
  bool IsDragging() const { return this->WidgetState == Active; }

 protected:
  ToolWidget();
  ~ToolWidget() override;

  enum WidgetStateType { Start = 0, Active };
  int WidgetState = Start;

  static void SelectAction(vtkAbstractWidget* widget);
  static void TranslateAction(vtkAbstractWidget* widget);
  static void MoveAction(vtkAbstractWidget* widget);
  static void EndSelectAction(vtkAbstractWidget* widget);
  static void CancelAction(vtkAbstractWidget* widget);

  /// Starts dragging the representation's current part at the current event position.
  void BeginDrag();
  void UpdateCursor(int state);

 private:
  ToolWidget(const ToolWidget&) = delete;
  void operator=(const ToolWidget&) = delete;
};

}  // namespace deepcut
