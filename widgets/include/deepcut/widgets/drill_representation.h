// SPDX-License-Identifier: MIT
#pragma once
/// @file drill_representation.h
/// The drill's geometry (VTK naming): a finite cylinder from axis end A to axis end B with a
/// radius, its side drawn translucent with outlined end rings and the axis; blue handles at A
/// and B and a yellow radius handle on the ring around A, on the side facing the camera's right.
/// The part under the cursor is drawn highlighted. Pair with DrillWidget. Include only in .cpp
/// files: it pulls in VTK.

#include <vtkNew.h>

#include "deepcut/widgets/tool_representation.h"

class vtkActor;
class vtkPolyData;
class vtkProperty;
class vtkSphereSource;

namespace deepcut {

class DrillRepresentation : public ToolRepresentation {
 public:
  static DrillRepresentation* New();
  vtkTypeMacro(DrillRepresentation, ToolRepresentation)

  /// The parts, as interaction states.
  enum InteractionStateType {
    OnEndA = 1,  ///< drag: axis end A
    OnEndB,      ///< drag: axis end B
    OnRadius,    ///< drag: the radius (distance from the cursor to the axis)
    OnCylinder,  ///< drag: the whole cylinder (its side or its axis)
    Translating  ///< the whole cylinder (middle button)
  };

  ///@{
  /// Axis ends, world space (default (0, 0, 1) and (0, 0, -1)).
  void SetEndA(const double p[3]);
  void SetEndB(const double p[3]);
  const double* GetEndA() const { return this->A; }
  const double* GetEndB() const { return this->B; }
  ///@}
  ///@{
  /// Radius, world units (default 0.1; clamped to >= 0).
  void SetRadius(double radius);
  double GetRadius() const { return this->Radius; }
  ///@}
  /// Where the radius handle is drawn (valid after a render or a pick).
  const double* GetRadiusHandle() const { return this->RadiusHandle; }

  ///@{
  /// Opacity of the cylinder's side (default 0.25).
  vtkSetClampMacro(SideOpacity, double, 0.0, 1.0);
  vtkGetMacro(SideOpacity, double);
  ///@}
  ///@{
  /// Sides of the drawn cylinder (default 48).
  vtkSetClampMacro(Resolution, int, 8, 512);
  vtkGetMacro(Resolution, int);
  ///@}

  /// Places a cylinder through the centre of `bounds` along z, a little longer than the box is
  /// deep, with a radius of 5% of the box's diagonal.
  void PlaceWidget(double bounds[6]) override;
  void BuildRepresentation() override;
  int ComputeInteractionState(int X, int Y, int modify = 0) override;
  void StartWidgetInteraction(double event_position[2]) override;
  void WidgetInteraction(double event_position[2]) override;
  void CancelWidgetInteraction() override;
  int GetTranslateState() const override { return Translating; }

 protected:
  DrillRepresentation();
  ~DrillRepresentation() override;
  std::vector<vtkActor*> GetToolActors() override;

 private:
  /// Unit vectors (u, v) perpendicular to the axis; u faces the camera's right when it can.
  void ComputeFrame(double u[3], double v[3]) const;

  double A[3] = {0.0, 0.0, 1.0};
  double B[3] = {0.0, 0.0, -1.0};
  double Radius = 0.1;
  double RadiusHandle[3] = {0.1, 0.0, 1.0};
  double Saved[7] = {};
  double SideOpacity = 0.25;
  int Resolution = 48;

  vtkNew<vtkSphereSource> Spheres[3];  // A, B, radius
  vtkNew<vtkActor> SphereActors[3];
  vtkNew<vtkPolyData> Side;  // the translucent side
  vtkNew<vtkActor> SideActor;
  vtkNew<vtkPolyData> Lines;  // end rings and axis
  vtkNew<vtkActor> LinesActor;
  vtkNew<vtkProperty> EndProperty, RadiusProperty, SideProperty, LineProperty;

  DrillRepresentation(const DrillRepresentation&) = delete;
  void operator=(const DrillRepresentation&) = delete;
};

}  // namespace deepcut
