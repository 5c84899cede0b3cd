// SPDX-License-Identifier: MIT
#include "deepcut/widgets/drill_representation.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkMath.h>
#include <vtkObjectFactory.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSphereSource.h>

#include <algorithm>
#include <cmath>

namespace deepcut {

vtkStandardNewMacro(DrillRepresentation);

namespace {

void copy3(double dst[3], const double src[3]) { std::copy(src, src + 3, dst); }

/// Distance from `p` to the infinite line through `a` and `b` (to `a` when a == b).
double distance_to_line(const double p[3], const double a[3], const double b[3]) {
  double w[3], d[3];
  vtkMath::Subtract(b, a, w);
  vtkMath::Subtract(p, a, d);
  const double len2 = vtkMath::Dot(w, w);
  if (len2 <= 0.0) return vtkMath::Norm(d);
  const double t = vtkMath::Dot(d, w) / len2;
  for (int k = 0; k < 3; ++k) d[k] -= t * w[k];
  return vtkMath::Norm(d);
}

}  // namespace

DrillRepresentation::DrillRepresentation() {
  this->EndProperty->SetColor(0.3, 0.7, 1.0);
  this->RadiusProperty->SetColor(1.0, 0.8, 0.2);
  this->SideProperty->SetColor(0.55, 0.8, 1.0);
  this->SideProperty->SetOpacity(this->SideOpacity);
  this->SideProperty->LightingOff();
  this->LineProperty->SetColor(0.3, 0.7, 1.0);
  this->LineProperty->SetLineWidth(2.0f);
  this->LineProperty->LightingOff();
  for (int i = 0; i < 3; ++i) {
    this->Spheres[i]->SetThetaResolution(16);
    this->Spheres[i]->SetPhiResolution(12);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(this->Spheres[i]->GetOutputPort());
    this->SphereActors[i]->SetMapper(mapper);
  }
  vtkNew<vtkPolyDataMapper> side_mapper;
  side_mapper->SetInputData(this->Side);
  this->SideActor->SetMapper(side_mapper);
  this->SideActor->SetProperty(this->SideProperty);
  // Blended in the opaque pass, after the other parts (see ScalpelRepresentation).
  this->SideActor->ForceOpaqueOn();
  vtkNew<vtkPolyDataMapper> line_mapper;
  line_mapper->SetInputData(this->Lines);
  this->LinesActor->SetMapper(line_mapper);
  this->LinesActor->SetProperty(this->LineProperty);
  this->LinesActor->PickableOff();
  this->BuildRepresentation();
}

DrillRepresentation::~DrillRepresentation() = default;

void DrillRepresentation::SetEndA(const double p[3]) {
  copy3(this->A, p);
  this->Modified();
}

void DrillRepresentation::SetEndB(const double p[3]) {
  copy3(this->B, p);
  this->Modified();
}

void DrillRepresentation::SetRadius(double radius) {
  this->Radius = std::max(0.0, radius);
  this->Modified();
}

void DrillRepresentation::PlaceWidget(double bounds[6]) {
  double b[6], c[3];
  this->AdjustBounds(bounds, b, c);
  const double depth = b[5] - b[4];
  const double diagonal =
      std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + depth * depth);
  this->A[0] = this->B[0] = c[0];
  this->A[1] = this->B[1] = c[1];
  this->A[2] = c[2] + 0.6 * depth;
  this->B[2] = c[2] - 0.6 * depth;
  this->Radius = 0.05 * diagonal;
  std::copy(b, b + 6, this->InitialBounds);
  this->Placed = 1;
  this->Modified();
}

std::vector<vtkActor*> DrillRepresentation::GetToolActors() {
  // The translucent side last, blended over the lines and handles.
  return {this->LinesActor, this->SphereActors[0], this->SphereActors[1], this->SphereActors[2],
          this->SideActor};
}

void DrillRepresentation::ComputeFrame(double u[3], double v[3]) const {
  double w[3];
  vtkMath::Subtract(this->B, this->A, w);
  if (vtkMath::Normalize(w) <= 0.0) w[0] = 0.0, w[1] = 0.0, w[2] = 1.0;
  double right[3] = {1.0, 0.0, 0.0};
  if (vtkRenderer* renderer = this->Renderer) {
    vtkCamera* camera = renderer->GetActiveCamera();
    double direction[3], up[3];
    camera->GetDirectionOfProjection(direction);
    camera->GetViewUp(up);
    vtkMath::Cross(direction, up, right);
  }
  // u: the camera's right without its axis part; if the axis points right, the camera's up.
  const double along = vtkMath::Dot(right, w);
  for (int k = 0; k < 3; ++k) u[k] = right[k] - along * w[k];
  if (vtkMath::Normalize(u) < 1e-3) {
    double helper[3] = {0.0, 1.0, 0.0};
    if (std::abs(w[1]) > 0.9) helper[0] = 1.0, helper[1] = 0.0;
    vtkMath::Cross(w, helper, u);
    vtkMath::Normalize(u);
  }
  vtkMath::Cross(w, u, v);
}

void DrillRepresentation::BuildRepresentation() {
  double u[3], v[3];
  this->ComputeFrame(u, v);
  for (int k = 0; k < 3; ++k) this->RadiusHandle[k] = this->A[k] + this->Radius * u[k];
  const double* centers[3] = {this->A, this->B, this->RadiusHandle};
  const int parts[3] = {OnEndA, OnEndB, OnRadius};
  for (int i = 0; i < 3; ++i) {
    this->Spheres[i]->SetCenter(centers[i][0], centers[i][1], centers[i][2]);
    this->Spheres[i]->SetRadius(this->WorldSizeOfPixels(centers[i], this->HandlePixels));
    this->SphereActors[i]->SetProperty(
        this->PartProperty(parts[i], i == 2 ? this->RadiusProperty.Get() : this->EndProperty.Get()));
  }

  const int n = this->Resolution;
  vtkNew<vtkPoints> points;
  points->SetNumberOfPoints(2 * n + 2);
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * vtkMath::Pi() * i / n;
    const double c = this->Radius * std::cos(t), s = this->Radius * std::sin(t);
    points->SetPoint(i, this->A[0] + c * u[0] + s * v[0], this->A[1] + c * u[1] + s * v[1],
                     this->A[2] + c * u[2] + s * v[2]);
    points->SetPoint(n + i, this->B[0] + c * u[0] + s * v[0], this->B[1] + c * u[1] + s * v[1],
                     this->B[2] + c * u[2] + s * v[2]);
  }
  points->SetPoint(2 * n, this->A);
  points->SetPoint(2 * n + 1, this->B);
  vtkNew<vtkCellArray> quads, lines;
  for (int i = 0; i < n; ++i) {
    const vtkIdType j = (i + 1) % n;
    const vtkIdType quad[4] = {i, j, n + j, n + i};
    quads->InsertNextCell(4, quad);
    const vtkIdType ring_a[2] = {i, j}, ring_b[2] = {n + i, n + j};
    lines->InsertNextCell(2, ring_a);
    lines->InsertNextCell(2, ring_b);
  }
  const vtkIdType axis[2] = {2 * n, 2 * n + 1};
  lines->InsertNextCell(2, axis);
  this->Side->SetPoints(points);
  this->Side->SetPolys(quads);
  this->Lines->SetPoints(points);
  this->Lines->SetLines(lines);

  this->SideProperty->SetOpacity(this->SideOpacity);
  const bool whole = this->HighlightedPart == OnCylinder || this->HighlightedPart == Translating;
  this->LinesActor->SetProperty(whole ? this->HighlightProperty.Get() : this->LineProperty.Get());
  this->BuildTime.Modified();
}

int DrillRepresentation::ComputeInteractionState(int X, int Y, int) {
  this->BuildRepresentation();
  const int handle = this->PickHandle({this->A, this->B, this->RadiusHandle}, X, Y);
  static const int kParts[3] = {OnEndA, OnEndB, OnRadius};
  if (handle >= 0) {
    // The radius handle sits on A's ring: prefer it when both are under the cursor.
    const int radius = this->PickHandle({this->RadiusHandle}, X, Y);
    this->InteractionState = radius == 0 ? OnRadius : kParts[handle];
    return this->InteractionState;
  }
  double position[3];
  if (this->PickActor(this->SideActor, X, Y, position)) {
    copy3(this->Anchor, position);
    this->InteractionState = OnCylinder;
  } else if (this->DisplayDistanceToSegment(this->A, this->B, X, Y) <= this->PickTolerance) {
    for (int k = 0; k < 3; ++k) this->Anchor[k] = 0.5 * (this->A[k] + this->B[k]);
    this->InteractionState = OnCylinder;
  } else {
    this->InteractionState = Outside;
  }
  return this->InteractionState;
}

void DrillRepresentation::StartWidgetInteraction(double event_position[2]) {
  this->LastEventPosition[0] = event_position[0];
  this->LastEventPosition[1] = event_position[1];
  copy3(this->Saved, this->A);
  copy3(this->Saved + 3, this->B);
  this->Saved[6] = this->Radius;
  switch (this->InteractionState) {
    case OnEndA:
      copy3(this->Anchor, this->A);
      break;
    case OnEndB:
      copy3(this->Anchor, this->B);
      break;
    case OnRadius:
      copy3(this->Anchor, this->RadiusHandle);
      break;
    case Translating:
      for (int k = 0; k < 3; ++k) this->Anchor[k] = 0.5 * (this->A[k] + this->B[k]);
      break;
    default:  // OnCylinder: the picked point, stored by ComputeInteractionState
      break;
  }
}

void DrillRepresentation::WidgetInteraction(double event_position[2]) {
  if (this->InteractionState == OnRadius) {
    double p[3];
    this->DisplayToWorldAt(this->Anchor, event_position[0], event_position[1], p);
    this->LastEventPosition[0] = event_position[0];
    this->LastEventPosition[1] = event_position[1];
    this->Radius = distance_to_line(p, this->A, this->B);
    this->Modified();
    return;
  }
  double delta[3];
  this->ViewPlaneMotion(this->Anchor, event_position, delta);
  const bool move_a = this->InteractionState != OnEndB, move_b = this->InteractionState != OnEndA;
  if (this->InteractionState == Outside) return;
  for (int k = 0; k < 3; ++k) {
    this->Anchor[k] += delta[k];
    if (move_a) this->A[k] += delta[k];
    if (move_b) this->B[k] += delta[k];
  }
  this->Modified();
}

void DrillRepresentation::CancelWidgetInteraction() {
  copy3(this->A, this->Saved);
  copy3(this->B, this->Saved + 3);
  this->Radius = this->Saved[6];
  this->Modified();
}

}  // namespace deepcut
