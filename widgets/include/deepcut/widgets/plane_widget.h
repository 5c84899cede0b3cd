// SPDX-License-Identifier: MIT
#pragma once
/// @file plane_widget.h
/// The cutting-plane widget (VTK naming): VTK's vtkImplicitPlaneWidget2 with the studio's look
/// (PlaneRepresentation) and without the right-button scaling, so a right drag always zooms
/// the camera. Observers of InteractionEvent read the plane back with
/// GetPlaneRepresentation()->GetOrigin() / GetNormal(). Include only in .cpp files.
///
/// @par Event Bindings:
/// By default the widget responds to these VTK events of its interactor:
/// <pre>
/// Over the normal arrow:
///   LeftButtonPressEvent   - select the normal
///   MouseMoveEvent         - rotate the normal about the origin point
///   LeftButtonReleaseEvent - release it
/// Over the origin point (sphere):
///   LeftButtonPressEvent   - select the origin
///   MouseMoveEvent         - move the origin within the plane
///   LeftButtonReleaseEvent - release it
/// Over the plane (translucent, cropped to the model's box):
///   LeftButtonPressEvent   - select the plane
///   MouseMoveEvent         - push the plane along its normal
///   LeftButtonReleaseEvent - release it
/// Over any part:
///   MiddleButtonPressEvent / MouseMoveEvent / MiddleButtonReleaseEvent - move the plane
///   MouseMoveEvent without a button - highlight the part
/// Keys (the view has the focus):
///   Up / Right             - push the plane along its normal
///   Down / Left            - push the plane against its normal
/// </pre>
/// Over no part every event goes on to the camera (interactor style).
///
/// @par Event Bindings:
/// The vtkWidgetEventTranslator maps these to vtkWidgetEvent::Select, EndSelect, Translate,
/// EndTranslate, Move, Up and Down. The widget in turn invokes on itself:
/// <pre>
///   vtkCommand::StartInteractionEvent (on Select and Translate over a part)
///   vtkCommand::InteractionEvent      (on Move while dragging, Up and Down)
///   vtkCommand::EndInteractionEvent   (on EndSelect and EndTranslate)
/// </pre>

#include <vtkImplicitPlaneWidget2.h>

#include "deepcut/widgets/plane_representation.h"

namespace deepcut {

class PlaneWidget : public vtkImplicitPlaneWidget2 {
 public:
  static PlaneWidget* New();
  vtkTypeMacro(PlaneWidget, vtkImplicitPlaneWidget2)

  PlaneRepresentation* GetPlaneRepresentation() {
    return static_cast<PlaneRepresentation*>(this->GetRepresentation());
  }
  void CreateDefaultRepresentation() override;

 protected:
  PlaneWidget();
  ~PlaneWidget() override = default;

 private:
  PlaneWidget(const PlaneWidget&) = delete;
  void operator=(const PlaneWidget&) = delete;
};

}  // namespace deepcut
