// SPDX-License-Identifier: MIT
#include "deepcut/widgets/scalpel_widget.h"

#include <vtkNew.h>
#include <vtkObjectFactory.h>

namespace deepcut {

vtkStandardNewMacro(ScalpelWidget);

void ScalpelWidget::CreateDefaultRepresentation() {
  if (this->WidgetRep) return;
  vtkNew<ScalpelRepresentation> representation;
  this->SetWidgetRepresentation(representation);
}

}  // namespace deepcut
