// SPDX-License-Identifier: MIT
#pragma once
/// @file scalpel_representation.h
/// The scalpel's geometry (VTK naming): a blade segment (handle point, tip point) at a start
/// pose and at an end pose, the swept quad between them drawn translucent. Handles are blue
/// spheres, tips orange, blades white lines; the part under the cursor is drawn highlighted.
/// Pair with ScalpelWidget. Include only in .cpp files: it pulls in VTK.

#include <vtkNew.h>

#include "deepcut/widgets/tool_representation.h"

class vtkActor;
class vtkLineSource;
class vtkPolyData;
class vtkProperty;
class vtkSphereSource;

namespace deepcut {

class ScalpelRepresentation : public ToolRepresentation {
 public:
  static ScalpelRepresentation* New();
  vtkTypeMacro(ScalpelRepresentation, ToolRepresentation)

  /// The parts, as interaction states.
  enum InteractionStateType {
    OnStartHandle = 1,  ///< drag: the start pose's handle point
    OnStartTip,         ///< drag: the start pose's tip point
    OnEndHandle,        ///< drag: the end pose's handle point
    OnEndTip,           ///< drag: the end pose's tip point
    OnStartBlade,       ///< drag: the whole start pose (handle and tip)
    OnEndBlade,         ///< drag: the whole end pose
    OnQuad,             ///< drag: the whole scalpel
    Translating         ///< the whole scalpel (middle button)
  };

  ///@{
  /// The blade poses, world space. Setting them does not invoke interaction events.
  /// Default: a blade from (0, 0, 1) to (0, 0, 0) sweeping from y = 0.5 to y = -0.5.
  void SetStartHandle(const double p[3]);
  void SetStartTip(const double p[3]);
  void SetEndHandle(const double p[3]);
  void SetEndTip(const double p[3]);
  const double* GetStartHandle() const { return this->Points[0]; }
  const double* GetStartTip() const { return this->Points[1]; }
  const double* GetEndHandle() const { return this->Points[2]; }
  const double* GetEndTip() const { return this->Points[3]; }
  ///@}

  ///@{
  /// Opacity of the swept quad (default 0.3).
  vtkSetClampMacro(QuadOpacity, double, 0.0, 1.0);
  vtkGetMacro(QuadOpacity, double);
  ///@}

  /// Places a default blade in `bounds`: pointing along -z from in front of the box to its
  /// centre, sweeping down through the middle third of its height.
  void PlaceWidget(double bounds[6]) override;
  void BuildRepresentation() override;
  int ComputeInteractionState(int X, int Y, int modify = 0) override;
  void StartWidgetInteraction(double event_position[2]) override;
  void WidgetInteraction(double event_position[2]) override;
  void CancelWidgetInteraction() override;
  int GetTranslateState() const override { return Translating; }

 protected:
  ScalpelRepresentation();
  ~ScalpelRepresentation() override;
  std::vector<vtkActor*> GetToolActors() override;

 private:
  /// start handle, start tip, end handle, end tip
  double Points[4][3] = {{0.0, 0.5, 1.0}, {0.0, 0.5, 0.0}, {0.0, -0.5, 1.0}, {0.0, -0.5, 0.0}};
  double SavedPoints[4][3] = {};
  double QuadOpacity = 0.3;

  vtkNew<vtkSphereSource> Spheres[4];
  vtkNew<vtkActor> SphereActors[4];
  vtkNew<vtkLineSource> Blades[2];
  vtkNew<vtkActor> BladeActors[2];
  vtkNew<vtkPolyData> Quad;
  vtkNew<vtkActor> QuadActor;
  vtkNew<vtkProperty> HandleProperty, TipProperty, BladeProperty, QuadProperty;

  ScalpelRepresentation(const ScalpelRepresentation&) = delete;
  void operator=(const ScalpelRepresentation&) = delete;
};

}  // namespace deepcut
