// SPDX-License-Identifier: MIT
#pragma once
/// @file scalpel_widget.h
/// The scalpel widget (VTK naming): drag a blade at its start and end pose to define a tear.
/// Pair with ScalpelRepresentation (created by default). Observers of InteractionEvent read the
/// poses back with GetScalpelRepresentation()->GetStartHandle() etc. Include only in .cpp files.
///
/// @par Event Bindings:
/// By default the widget responds to these VTK events of its interactor:
/// <pre>
/// Over a handle point (blue) or a tip point (orange) of either pose:
///   LeftButtonPressEvent   - select that point
///   MouseMoveEvent         - move it in the view plane through it
///   LeftButtonReleaseEvent - release it
/// Over a blade (the white segment of one pose):
///   LeftButtonPressEvent   - select that pose
///   MouseMoveEvent         - move the pose's handle and tip together in the view plane
///   LeftButtonReleaseEvent - release it
/// Over the swept quad (translucent):
///   LeftButtonPressEvent   - select the whole scalpel
///   MouseMoveEvent         - move both poses together in the view plane
///   LeftButtonReleaseEvent - release it
/// Over any part:
///   MiddleButtonPressEvent / MouseMoveEvent / MiddleButtonReleaseEvent - move the whole scalpel
///   MouseMoveEvent without a button - highlight the part, hand cursor
/// While dragging:
///   KeyPressEvent Escape   - put the scalpel back where the drag started
/// </pre>
/// Over no part every event goes on to the camera (interactor style).
///
/// @par Event Bindings:
/// The vtkWidgetEventTranslator maps these to vtkWidgetEvent::Select, EndSelect, Translate,
/// EndTranslate, Move and Reset. The widget in turn invokes on itself:
/// <pre>
///   vtkCommand::StartInteractionEvent (on Select and Translate over a part)
///   vtkCommand::InteractionEvent      (on Move while dragging, and on Reset)
///   vtkCommand::EndInteractionEvent   (on EndSelect, EndTranslate and Reset)
/// </pre>

#include "deepcut/widgets/scalpel_representation.h"
#include "deepcut/widgets/tool_widget.h"

namespace deepcut {

class ScalpelWidget : public ToolWidget {
 public:
  static ScalpelWidget* New();
  vtkTypeMacro(ScalpelWidget, ToolWidget)

  void SetRepresentation(ScalpelRepresentation* representation) {
    this->SetWidgetRepresentation(representation);
  }
  ScalpelRepresentation* GetScalpelRepresentation() {
    return static_cast<ScalpelRepresentation*>(this->GetRepresentation());
  }
  void CreateDefaultRepresentation() override;

 protected:
  ScalpelWidget() = default;
  ~ScalpelWidget() override = default;

 private:
  ScalpelWidget(const ScalpelWidget&) = delete;
  void operator=(const ScalpelWidget&) = delete;
};

}  // namespace deepcut
