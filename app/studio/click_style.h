// SPDX-License-Identifier: MIT
#pragma once
// The studio view's camera interaction (scene_view.cpp): a VTK trackball style that reports
// clicks, offers left drags to the active tool first and leaves the keyboard to the menus.

#include <vtkInteractorStyleTrackballCamera.h>

#include <functional>

namespace deepcut::studio {

/// Trackball camera (left rotate, middle pan, wheel/right zoom) that reports clicks and leaves
/// the keyboard to the studio's menus (VTK's own keys would quit or restyle behind its back).
class ClickStyle : public vtkInteractorStyleTrackballCamera {
 public:
  static ClickStyle* New();
  vtkTypeMacro(ClickStyle, vtkInteractorStyleTrackballCamera)

  void OnChar() override {}
  void OnLeftButtonDown() override;
  void OnMouseMove() override;
  void OnLeftButtonUp() override;

  std::function<void(int, int)> on_click;
  /// A left press at display (x, y): true when a tool takes the drag.
  std::function<bool(int, int)> on_press;
  /// The taken drag moved (`released` false) or ended (true) at display (x, y).
  std::function<void(int, int, bool released)> on_drag;

 private:
  int press_[2] = {0, 0};
  bool dragging_ = false;
};

}  // namespace deepcut::studio
