// SPDX-License-Identifier: MIT
#include "deepcut/widgets/drill_widget.h"

#include <vtkNew.h>
#include <vtkObjectFactory.h>

namespace deepcut {

vtkStandardNewMacro(DrillWidget);

void DrillWidget::CreateDefaultRepresentation() {
  if (this->WidgetRep) return;
  vtkNew<DrillRepresentation> representation;
  this->SetWidgetRepresentation(representation);
}

}  // namespace deepcut
