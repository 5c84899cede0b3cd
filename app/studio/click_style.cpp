// SPDX-License-Identifier: MIT
#include "click_style.h"

#include <vtkObjectFactory.h>
#include <vtkRenderWindowInteractor.h>

#include <cstdlib>

namespace deepcut::studio {

vtkStandardNewMacro(ClickStyle);

void ClickStyle::OnLeftButtonDown() {
  GetInteractor()->GetEventPosition(press_);
  if (on_press && on_press(press_[0], press_[1])) {
    dragging_ = true;  // a tool took the drag: the camera stays
    return;
  }
  Superclass::OnLeftButtonDown();
}

void ClickStyle::OnMouseMove() {
  if (dragging_) {
    int p[2];
    GetInteractor()->GetEventPosition(p);
    if (on_drag) on_drag(p[0], p[1], false);
    return;
  }
  Superclass::OnMouseMove();
}

void ClickStyle::OnLeftButtonUp() {
  if (dragging_) {
    dragging_ = false;
    int p[2];
    GetInteractor()->GetEventPosition(p);
    if (on_drag) on_drag(p[0], p[1], true);
    return;
  }
  Superclass::OnLeftButtonUp();
  int p[2];
  GetInteractor()->GetEventPosition(p);
  if (on_click && std::abs(p[0] - press_[0]) <= 3 && std::abs(p[1] - press_[1]) <= 3) on_click(p[0], p[1]);
}

}  // namespace deepcut::studio
