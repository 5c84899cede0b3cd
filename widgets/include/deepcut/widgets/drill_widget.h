// SPDX-License-Identifier: MIT
#pragma once
/// @file drill_widget.h
/// The drill widget (VTK naming): place a finite cylinder by its axis ends and its radius.
/// Pair with DrillRepresentation (created by default). Observers of InteractionEvent read the
/// cylinder back with GetDrillRepresentation()->GetEndA(), GetEndB(), GetRadius(). Include
/// only in .cpp files.
///
/// @par Event Bindings:
/// By default the widget responds to these VTK events of its interactor:
/// <pre>
/// Over axis end A or B (blue sphere):
///   LeftButtonPressEvent   - select that end
///   MouseMoveEvent         - move it in the view plane through it (the other end stays)
///   LeftButtonReleaseEvent - release it
/// Over the radius handle (yellow sphere on the ring around A):
///   LeftButtonPressEvent   - select the radius
///   MouseMoveEvent         - radius = distance from the cursor (in the view plane through the
///                            handle) to the axis
///   LeftButtonReleaseEvent - release it
/// Over the cylinder's side (translucent) or its axis:
///   LeftButtonPressEvent   - select the whole cylinder
///   MouseMoveEvent         - move both ends together in the view plane
///   LeftButtonReleaseEvent - release it
/// Over any part:
///   MiddleButtonPressEvent / MouseMoveEvent / MiddleButtonReleaseEvent - move the whole cylinder
///   MouseMoveEvent without a button - highlight the part, hand cursor
/// While dragging:
///   KeyPressEvent Escape   - put the cylinder back where the drag started
/// </pre>
/// Over no part every event goes on to the camera (interactor style). When both ends project
/// to the same point (looking down the axis) the end nearer the camera is picked.
///
/// @par Event Bindings:
/// The vtkWidgetEventTranslator maps these to vtkWidgetEvent::Select, EndSelect, Translate,
/// EndTranslate, Move and Reset. The widget in turn invokes on itself:
/// <pre>
///   vtkCommand::StartInteractionEvent (on Select and Translate over a part)
///   vtkCommand::InteractionEvent      (on Move while dragging, and on Reset)
///   vtkCommand::EndInteractionEvent   (on EndSelect, EndTranslate and Reset)
/// </pre>

#include "deepcut/widgets/drill_representation.h"
#include "deepcut/widgets/tool_widget.h"

namespace deepcut {

class DrillWidget : public ToolWidget {
 public:
  static DrillWidget* New();
  vtkTypeMacro(DrillWidget, ToolWidget)

  void SetRepresentation(DrillRepresentation* representation) {
    this->SetWidgetRepresentation(representation);
  }
  DrillRepresentation* GetDrillRepresentation() {
    return static_cast<DrillRepresentation*>(this->GetRepresentation());
  }
  void CreateDefaultRepresentation() override;

 protected:
  DrillWidget() = default;
  ~DrillWidget() override = default;

 private:
  DrillWidget(const DrillWidget&) = delete;
  void operator=(const DrillWidget&) = delete;
};

}  // namespace deepcut
