// SPDX-License-Identifier: MIT
#pragma once
/// @file tool_representation.h
/// Shared base of the scalpel and drill representations (VTK naming): point handles drawn as
/// spheres of a fixed size in pixels, picked in display space; line parts picked by their
/// projected distance; translucent bodies picked with a vtkCellPicker; every drag moves in the
/// view plane through the grabbed point. Include only in .cpp files: it pulls in VTK.

#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkWidgetRepresentation.h>

#include <vector>

class vtkActor;
class vtkCellPicker;
class vtkProperty;
class vtkPropCollection;

namespace deepcut {

class ToolRepresentation : public vtkWidgetRepresentation {
 public:
  vtkTypeMacro(ToolRepresentation, vtkWidgetRepresentation)

  /// Interaction state 0 is "outside" in every subclass; parts are numbered from 1.
  static constexpr int Outside = 0;

  /// Sets the interaction state (a part, or the subclass's translate state) without a pick:
  /// the widget uses it for middle-button translation.
  void SetInteractionState(int state);
  /// The state that translates the whole tool (middle button drag).
  virtual int GetTranslateState() const = 0;

  /// Draws the part of the current interaction state highlighted (hover and drag feedback).
  void Highlight(int highlight_on) override;

  ///@{
  /// Handle sphere radius in pixels (default 7).
  vtkSetClampMacro(HandlePixels, double, 1.0, 100.0);
  vtkGetMacro(HandlePixels, double);
  ///@}
  ///@{
  /// Extra pick margin in pixels around handles and lines (default 5).
  vtkSetClampMacro(PickTolerance, double, 0.0, 100.0);
  vtkGetMacro(PickTolerance, double);
  ///@}

  /// Puts the tool back where it was when the current drag started (Escape while dragging).
  virtual void CancelWidgetInteraction() = 0;

  // Rendering: the representation is one prop made of the subclass's actors.
  double* GetBounds() VTK_SIZEHINT(6) override;
  void GetActors(vtkPropCollection* actors) override;
  void ReleaseGraphicsResources(vtkWindow* window) override;
  int RenderOpaqueGeometry(vtkViewport* viewport) override;
  int RenderTranslucentPolygonalGeometry(vtkViewport* viewport) override;
  vtkTypeBool HasTranslucentPolygonalGeometry() override;

 protected:
  ToolRepresentation();
  ~ToolRepresentation() override;

  /// Every actor of the representation, in drawing order.
  virtual std::vector<vtkActor*> GetToolActors() = 0;

  /// Display coordinates (pixels, origin bottom left; z the depth) of world point `world`.
  /// @returns false without a renderer.
  bool WorldToDisplay(const double world[3], double display[3]) const;
  /// The world point at display position (x, y) on the view plane through `anchor`.
  void DisplayToWorldAt(const double anchor[3], double x, double y, double world[3]) const;
  /// World length of `pixels` pixels at `position` (for sizing handles); 1 without a renderer.
  double WorldSizeOfPixels(const double position[3], double pixels) const;
  /// World motion, in the view plane through `anchor`, of the cursor from the last event
  /// position to `event_position`; updates the last event position.
  void ViewPlaneMotion(const double anchor[3], const double event_position[2], double delta[3]);
  /// Index of the handle whose centre is nearest to (x, y) within its radius plus the pick
  /// tolerance (ties: nearest to the camera), or -1.
  int PickHandle(const std::vector<const double*>& centers, int x, int y) const;
  /// Distance in pixels from (x, y) to the projection of segment (a, b).
  double DisplayDistanceToSegment(const double a[3], const double b[3], int x, int y) const;
  /// Picks `actor` at (x, y); on a hit stores the world point in `position`.
  bool PickActor(vtkActor* actor, int x, int y, double position[3]);

  /// Property of a part: the highlight property while it is highlighted, else `normal`.
  vtkProperty* PartProperty(int part, vtkProperty* normal) const;

  double HandlePixels = 7.0;
  double PickTolerance = 5.0;
  int HighlightedPart = Outside;
  double LastEventPosition[2] = {0.0, 0.0};
  double Anchor[3] = {0.0, 0.0, 0.0};  ///< the grabbed world point of the current drag
  double Bounds[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  vtkNew<vtkProperty> HighlightProperty;
  vtkNew<vtkCellPicker> BodyPicker;

 private:
  ToolRepresentation(const ToolRepresentation&) = delete;
  void operator=(const ToolRepresentation&) = delete;
};

}  // namespace deepcut
