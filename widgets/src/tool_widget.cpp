// SPDX-License-Identifier: MIT
#include "deepcut/widgets/tool_widget.h"

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkEvent.h>
#include <vtkRenderWindow.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkWidgetCallbackMapper.h>
#include <vtkWidgetEvent.h>

#include "deepcut/widgets/tool_representation.h"

namespace deepcut {

ToolWidget::ToolWidget() {
  this->ManagesCursor = 1;
  vtkWidgetCallbackMapper* map = this->CallbackMapper;
  map->SetCallbackMethod(vtkCommand::LeftButtonPressEvent, vtkWidgetEvent::Select, this,
                         ToolWidget::SelectAction);
  map->SetCallbackMethod(vtkCommand::LeftButtonReleaseEvent, vtkWidgetEvent::EndSelect, this,
                         ToolWidget::EndSelectAction);
  map->SetCallbackMethod(vtkCommand::MiddleButtonPressEvent, vtkWidgetEvent::Translate, this,
                         ToolWidget::TranslateAction);
  map->SetCallbackMethod(vtkCommand::MiddleButtonReleaseEvent, vtkWidgetEvent::EndTranslate, this,
                         ToolWidget::EndSelectAction);
  map->SetCallbackMethod(vtkCommand::MouseMoveEvent, vtkWidgetEvent::Move, this, ToolWidget::MoveAction);
  map->SetCallbackMethod(vtkCommand::KeyPressEvent, vtkEvent::AnyModifier, 27, 1, "Escape",
                         vtkWidgetEvent::Reset, this, ToolWidget::CancelAction);
}

ToolWidget::~ToolWidget() = default;

void ToolWidget::UpdateCursor(int state) {
  if (!this->ManagesCursor) return;
  this->RequestCursorShape(state == ToolRepresentation::Outside ? VTK_CURSOR_DEFAULT : VTK_CURSOR_HAND);
}

void ToolWidget::BeginDrag() {
  auto* rep = static_cast<ToolRepresentation*>(this->WidgetRep);
  const int* position = this->Interactor->GetEventPosition();
  double e[2] = {static_cast<double>(position[0]), static_cast<double>(position[1])};
  this->GrabFocus(this->EventCallbackCommand);
  rep->StartWidgetInteraction(e);
  rep->Highlight(1);
  this->WidgetState = Active;
  this->EventCallbackCommand->SetAbortFlag(1);
  this->StartInteraction();
  this->InvokeEvent(vtkCommand::StartInteractionEvent, nullptr);
  this->Render();
}

void ToolWidget::SelectAction(vtkAbstractWidget* widget) {
  auto* self = static_cast<ToolWidget*>(widget);
  if (self->WidgetState == Active || !self->WidgetRep) return;
  const int* position = self->Interactor->GetEventPosition();
  if (self->WidgetRep->ComputeInteractionState(position[0], position[1]) == ToolRepresentation::Outside)
    return;
  self->BeginDrag();
}

void ToolWidget::TranslateAction(vtkAbstractWidget* widget) {
  auto* self = static_cast<ToolWidget*>(widget);
  if (self->WidgetState == Active || !self->WidgetRep) return;
  auto* rep = static_cast<ToolRepresentation*>(self->WidgetRep);
  const int* position = self->Interactor->GetEventPosition();
  if (rep->ComputeInteractionState(position[0], position[1]) == ToolRepresentation::Outside) return;
  rep->SetInteractionState(rep->GetTranslateState());
  self->BeginDrag();
}

void ToolWidget::MoveAction(vtkAbstractWidget* widget) {
  auto* self = static_cast<ToolWidget*>(widget);
  if (!self->WidgetRep) return;
  auto* rep = static_cast<ToolRepresentation*>(self->WidgetRep);
  const int* position = self->Interactor->GetEventPosition();
  if (self->WidgetState == Start) {
    // Hover: highlight the part under the cursor; the event goes on to the camera.
    const int before = rep->GetInteractionState();
    const int state = rep->ComputeInteractionState(position[0], position[1]);
    self->UpdateCursor(state);
    if (state != before) {
      rep->Highlight(state != ToolRepresentation::Outside);
      self->Render();
    }
    return;
  }
  double e[2] = {static_cast<double>(position[0]), static_cast<double>(position[1])};
  rep->WidgetInteraction(e);
  self->EventCallbackCommand->SetAbortFlag(1);
  self->InvokeEvent(vtkCommand::InteractionEvent, nullptr);
  self->Render();
}

void ToolWidget::EndSelectAction(vtkAbstractWidget* widget) {
  auto* self = static_cast<ToolWidget*>(widget);
  if (self->WidgetState != Active) return;
  auto* rep = static_cast<ToolRepresentation*>(self->WidgetRep);
  const int* position = self->Interactor->GetEventPosition();
  double e[2] = {static_cast<double>(position[0]), static_cast<double>(position[1])};
  rep->EndWidgetInteraction(e);
  self->WidgetState = Start;
  self->ReleaseFocus();
  rep->ComputeInteractionState(position[0], position[1]);
  rep->Highlight(rep->GetInteractionState() != ToolRepresentation::Outside);
  self->EventCallbackCommand->SetAbortFlag(1);
  self->EndInteraction();
  self->InvokeEvent(vtkCommand::EndInteractionEvent, nullptr);
  self->Render();
}

void ToolWidget::CancelAction(vtkAbstractWidget* widget) {
  auto* self = static_cast<ToolWidget*>(widget);
  if (self->WidgetState != Active) return;
  auto* rep = static_cast<ToolRepresentation*>(self->WidgetRep);
  rep->CancelWidgetInteraction();
  self->WidgetState = Start;
  self->ReleaseFocus();
  rep->SetInteractionState(ToolRepresentation::Outside);
  rep->Highlight(0);
  self->EventCallbackCommand->SetAbortFlag(1);
  self->InvokeEvent(vtkCommand::InteractionEvent, nullptr);
  self->EndInteraction();
  self->InvokeEvent(vtkCommand::EndInteractionEvent, nullptr);
  self->Render();
}

}  // namespace deepcut
