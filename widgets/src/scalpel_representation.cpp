// SPDX-License-Identifier: MIT
#include "deepcut/widgets/scalpel_representation.h"

#include <vtkActor.h>
#include <vtkCellArray.h>
#include <vtkLineSource.h>
#include <vtkObjectFactory.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkSphereSource.h>

#include <algorithm>

namespace deepcut {

vtkStandardNewMacro(ScalpelRepresentation);

ScalpelRepresentation::ScalpelRepresentation() {
  this->HandleProperty->SetColor(0.3, 0.7, 1.0);
  this->TipProperty->SetColor(1.0, 0.45, 0.2);
  this->BladeProperty->SetColor(0.92, 0.92, 0.95);
  this->BladeProperty->SetLineWidth(3.0f);
  this->BladeProperty->LightingOff();
  this->QuadProperty->SetColor(0.85, 0.9, 1.0);
  this->QuadProperty->SetOpacity(this->QuadOpacity);
  this->QuadProperty->LightingOff();
  for (int i = 0; i < 4; ++i) {
    this->Spheres[i]->SetThetaResolution(16);
    this->Spheres[i]->SetPhiResolution(12);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(this->Spheres[i]->GetOutputPort());
    this->SphereActors[i]->SetMapper(mapper);
  }
  for (int i = 0; i < 2; ++i) {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(this->Blades[i]->GetOutputPort());
    this->BladeActors[i]->SetMapper(mapper);
  }
  vtkNew<vtkPoints> points;
  points->SetNumberOfPoints(4);
  vtkNew<vtkCellArray> polys;
  const vtkIdType quad[4] = {0, 1, 3, 2};  // start handle, start tip, end tip, end handle
  polys->InsertNextCell(4, quad);
  this->Quad->SetPoints(points);
  this->Quad->SetPolys(polys);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(this->Quad);
  this->QuadActor->SetMapper(mapper);
  // Blended in the opaque pass, after the other parts: the translucent pass (order-independent
  // transparency) stripes a layered view on some OpenGL drivers.
  this->QuadActor->ForceOpaqueOn();
  this->BuildRepresentation();
}

ScalpelRepresentation::~ScalpelRepresentation() = default;

namespace {
void set_point(double (&dst)[3], const double src[3]) { std::copy(src, src + 3, dst); }
}  // namespace

void ScalpelRepresentation::SetStartHandle(const double p[3]) {
  set_point(this->Points[0], p);
  this->Modified();
}
void ScalpelRepresentation::SetStartTip(const double p[3]) {
  set_point(this->Points[1], p);
  this->Modified();
}
void ScalpelRepresentation::SetEndHandle(const double p[3]) {
  set_point(this->Points[2], p);
  this->Modified();
}
void ScalpelRepresentation::SetEndTip(const double p[3]) {
  set_point(this->Points[3], p);
  this->Modified();
}

void ScalpelRepresentation::PlaceWidget(double bounds[6]) {
  double b[6], c[3];
  this->AdjustBounds(bounds, b, c);
  const double depth = b[5] - b[4], height = b[3] - b[2];
  const double handle_z = b[5] + 0.5 * depth, sweep = height / 6.0;
  const double points[4][3] = {{c[0], c[1] + sweep, handle_z},
                               {c[0], c[1] + sweep, c[2]},
                               {c[0], c[1] - sweep, handle_z},
                               {c[0], c[1] - sweep, c[2]}};
  for (int i = 0; i < 4; ++i) set_point(this->Points[i], points[i]);
  std::copy(b, b + 6, this->InitialBounds);
  this->Placed = 1;
  this->Modified();
}

std::vector<vtkActor*> ScalpelRepresentation::GetToolActors() {
  // The translucent quad last, blended over the blades and spheres.
  return {this->BladeActors[0],  this->BladeActors[1],  this->SphereActors[0], this->SphereActors[1],
          this->SphereActors[2], this->SphereActors[3], this->QuadActor};
}

void ScalpelRepresentation::BuildRepresentation() {
  static const int kPointPart[4] = {OnStartHandle, OnStartTip, OnEndHandle, OnEndTip};
  for (int i = 0; i < 4; ++i) {
    this->Spheres[i]->SetCenter(this->Points[i]);
    this->Spheres[i]->SetRadius(this->WorldSizeOfPixels(this->Points[i], this->HandlePixels));
    const bool tip = i % 2 == 1;
    this->SphereActors[i]->SetProperty(
        this->PartProperty(kPointPart[i], tip ? this->TipProperty.Get() : this->HandleProperty.Get()));
  }
  for (int i = 0; i < 2; ++i) {
    this->Blades[i]->SetPoint1(this->Points[2 * i]);
    this->Blades[i]->SetPoint2(this->Points[2 * i + 1]);
    this->BladeActors[i]->SetProperty(
        this->PartProperty(i == 0 ? OnStartBlade : OnEndBlade, this->BladeProperty));
  }
  vtkPoints* points = this->Quad->GetPoints();
  for (int i = 0; i < 4; ++i) points->SetPoint(i, this->Points[i]);
  points->Modified();
  this->Quad->Modified();
  this->QuadProperty->SetOpacity(this->QuadOpacity);
  const bool whole = this->HighlightedPart == OnQuad || this->HighlightedPart == Translating;
  this->QuadActor->SetProperty(whole ? this->HighlightProperty.Get() : this->QuadProperty.Get());
  if (whole)
    this->HighlightProperty->SetOpacity(this->QuadOpacity);
  else
    this->HighlightProperty->SetOpacity(1.0);
  this->BuildTime.Modified();
}

int ScalpelRepresentation::ComputeInteractionState(int X, int Y, int) {
  const int handle =
      this->PickHandle({this->Points[0], this->Points[1], this->Points[2], this->Points[3]}, X, Y);
  static const int kPointPart[4] = {OnStartHandle, OnStartTip, OnEndHandle, OnEndTip};
  if (handle >= 0) {
    this->InteractionState = kPointPart[handle];
    return this->InteractionState;
  }
  const double start = this->DisplayDistanceToSegment(this->Points[0], this->Points[1], X, Y);
  const double end = this->DisplayDistanceToSegment(this->Points[2], this->Points[3], X, Y);
  if (std::min(start, end) <= this->PickTolerance) {
    this->InteractionState = start <= end ? OnStartBlade : OnEndBlade;
    return this->InteractionState;
  }
  double position[3];
  this->BuildRepresentation();
  this->InteractionState = this->PickActor(this->QuadActor, X, Y, position) ? OnQuad : Outside;
  if (this->InteractionState == OnQuad) std::copy(position, position + 3, this->Anchor);
  return this->InteractionState;
}

void ScalpelRepresentation::StartWidgetInteraction(double event_position[2]) {
  this->LastEventPosition[0] = event_position[0];
  this->LastEventPosition[1] = event_position[1];
  for (int i = 0; i < 4; ++i) set_point(this->SavedPoints[i], this->Points[i]);
  switch (this->InteractionState) {
    case OnStartHandle:
    case OnStartTip:
    case OnEndHandle:
    case OnEndTip:
      set_point(this->Anchor, this->Points[this->InteractionState - OnStartHandle]);
      break;
    case OnStartBlade:
    case OnEndBlade: {
      const int first = this->InteractionState == OnStartBlade ? 0 : 2;
      for (int k = 0; k < 3; ++k)
        this->Anchor[k] = 0.5 * (this->Points[first][k] + this->Points[first + 1][k]);
      break;
    }
    case Translating:
      for (int k = 0; k < 3; ++k)
        this->Anchor[k] =
            0.25 * (this->Points[0][k] + this->Points[1][k] + this->Points[2][k] + this->Points[3][k]);
      break;
    default:  // OnQuad: the picked point, stored by ComputeInteractionState
      break;
  }
}

void ScalpelRepresentation::WidgetInteraction(double event_position[2]) {
  double delta[3];
  this->ViewPlaneMotion(this->Anchor, event_position, delta);
  bool moved[4] = {false, false, false, false};
  switch (this->InteractionState) {
    case OnStartHandle:
    case OnStartTip:
    case OnEndHandle:
    case OnEndTip:
      moved[this->InteractionState - OnStartHandle] = true;
      break;
    case OnStartBlade:
      moved[0] = moved[1] = true;
      break;
    case OnEndBlade:
      moved[2] = moved[3] = true;
      break;
    case OnQuad:
    case Translating:
      moved[0] = moved[1] = moved[2] = moved[3] = true;
      break;
    default:
      return;
  }
  for (int k = 0; k < 3; ++k) this->Anchor[k] += delta[k];
  for (int i = 0; i < 4; ++i)
    if (moved[i])
      for (int k = 0; k < 3; ++k) this->Points[i][k] += delta[k];
  this->Modified();
}

void ScalpelRepresentation::CancelWidgetInteraction() {
  for (int i = 0; i < 4; ++i) set_point(this->Points[i], this->SavedPoints[i]);
  this->Modified();
}

}  // namespace deepcut
