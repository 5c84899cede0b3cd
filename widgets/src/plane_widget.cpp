// SPDX-License-Identifier: MIT
#include "deepcut/widgets/plane_widget.h"

#include <vtkCommand.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkProperty.h>
#include <vtkWidgetEventTranslator.h>

namespace deepcut {

vtkStandardNewMacro(PlaneRepresentation);
vtkStandardNewMacro(PlaneWidget);

PlaneRepresentation::PlaneRepresentation() {
  this->SetOutlineTranslation(0);
  this->SetScaleEnabled(0);
  this->SetOutsideBounds(1);
  this->SetConstrainToWidgetBounds(0);
  this->SetTubing(1);
  this->SetDrawOutline(0);
  this->GetPlaneProperty()->SetColor(0.3, 0.7, 1.0);
  this->GetPlaneProperty()->SetOpacity(0.22);
  this->GetSelectedPlaneProperty()->SetColor(0.5, 0.85, 1.0);
  this->GetSelectedPlaneProperty()->SetOpacity(0.35);
  this->GetNormalProperty()->SetColor(0.3, 0.7, 1.0);
  this->GetSelectedNormalProperty()->SetColor(1.0, 1.0, 0.55);
  this->SetEdgeColor(0.3, 0.7, 1.0);
}

PlaneWidget::PlaneWidget() {
  // Right drags zoom the camera even over the plane (the plane covers most of the model).
  this->EventTranslator->RemoveTranslation(vtkCommand::RightButtonPressEvent);
  this->EventTranslator->RemoveTranslation(vtkCommand::RightButtonReleaseEvent);
}

void PlaneWidget::CreateDefaultRepresentation() {
  if (this->WidgetRep) return;
  vtkNew<PlaneRepresentation> representation;
  this->SetRepresentation(representation);
}

}  // namespace deepcut
