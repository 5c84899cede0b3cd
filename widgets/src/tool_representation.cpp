// SPDX-License-Identifier: MIT
#include "deepcut/widgets/tool_representation.h"

#include <vtkActor.h>
#include <vtkCellPicker.h>
#include <vtkMath.h>
#include <vtkPropCollection.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace deepcut {

ToolRepresentation::ToolRepresentation() {
  this->InteractionState = Outside;
  this->HighlightProperty->SetColor(1.0, 1.0, 0.55);
  this->HighlightProperty->SetAmbient(0.4);
  this->HighlightProperty->SetLineWidth(4.0f);
  this->BodyPicker->PickFromListOn();
  this->BodyPicker->SetTolerance(0.002);
}

ToolRepresentation::~ToolRepresentation() = default;

void ToolRepresentation::SetInteractionState(int state) {
  if (this->InteractionState == state) return;
  this->InteractionState = state;
  this->Modified();
}

void ToolRepresentation::Highlight(int highlight_on) {
  const int part = highlight_on ? this->InteractionState : Outside;
  if (part == this->HighlightedPart) return;
  this->HighlightedPart = part;
  this->Modified();
}

vtkProperty* ToolRepresentation::PartProperty(int part, vtkProperty* normal) const {
  return part != Outside && part == this->HighlightedPart ? this->HighlightProperty.Get() : normal;
}

bool ToolRepresentation::WorldToDisplay(const double world[3], double display[3]) const {
  vtkRenderer* renderer = this->Renderer;
  if (!renderer) return false;
  renderer->SetWorldPoint(world[0], world[1], world[2], 1.0);
  renderer->WorldToDisplay();
  renderer->GetDisplayPoint(display);
  return true;
}

void ToolRepresentation::DisplayToWorldAt(const double anchor[3], double x, double y, double world[3]) const {
  double display[3];
  if (!this->WorldToDisplay(anchor, display)) {
    std::copy(anchor, anchor + 3, world);
    return;
  }
  vtkRenderer* renderer = this->Renderer;
  renderer->SetDisplayPoint(x, y, display[2]);
  renderer->DisplayToWorld();
  double h[4];
  renderer->GetWorldPoint(h);
  const double w = h[3] != 0.0 ? h[3] : 1.0;
  for (int k = 0; k < 3; ++k) world[k] = h[k] / w;
}

double ToolRepresentation::WorldSizeOfPixels(const double position[3], double pixels) const {
  double display[3];
  if (!this->WorldToDisplay(position, display)) return 1.0;
  double moved[3];
  this->DisplayToWorldAt(position, display[0] + pixels, display[1], moved);
  const double size = std::sqrt(vtkMath::Distance2BetweenPoints(position, moved));
  return size > 0.0 ? size : 1.0;
}

void ToolRepresentation::ViewPlaneMotion(const double anchor[3], const double event_position[2],
                                         double delta[3]) {
  double from[3], to[3];
  this->DisplayToWorldAt(anchor, this->LastEventPosition[0], this->LastEventPosition[1], from);
  this->DisplayToWorldAt(anchor, event_position[0], event_position[1], to);
  for (int k = 0; k < 3; ++k) delta[k] = to[k] - from[k];
  this->LastEventPosition[0] = event_position[0];
  this->LastEventPosition[1] = event_position[1];
}

int ToolRepresentation::PickHandle(const std::vector<const double*>& centers, int x, int y) const {
  int best = -1;
  double best_depth = std::numeric_limits<double>::max();
  for (std::size_t i = 0; i < centers.size(); ++i) {
    double display[3];
    if (!this->WorldToDisplay(centers[i], display)) return -1;
    const double d = std::hypot(display[0] - x, display[1] - y);
    if (d > this->HandlePixels + this->PickTolerance) continue;
    if (display[2] < best_depth) {
      best_depth = display[2];
      best = static_cast<int>(i);
    }
  }
  return best;
}

double ToolRepresentation::DisplayDistanceToSegment(const double a[3], const double b[3], int x,
                                                    int y) const {
  double da[3], db[3];
  if (!this->WorldToDisplay(a, da) || !this->WorldToDisplay(b, db)) return std::numeric_limits<double>::max();
  const double ex = db[0] - da[0], ey = db[1] - da[1];
  const double len2 = ex * ex + ey * ey;
  double t = len2 > 0.0 ? ((x - da[0]) * ex + (y - da[1]) * ey) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(da[0] + t * ex - x, da[1] + t * ey - y);
}

bool ToolRepresentation::PickActor(vtkActor* actor, int x, int y, double position[3]) {
  vtkRenderer* renderer = this->Renderer;
  if (!renderer || !actor || !actor->GetVisibility()) return false;
  this->BodyPicker->InitializePickList();
  this->BodyPicker->AddPickList(actor);
  if (!this->BodyPicker->Pick(x, y, 0.0, renderer) || this->BodyPicker->GetActor() != actor) return false;
  this->BodyPicker->GetPickPosition(position);
  return true;
}

double* ToolRepresentation::GetBounds() {
  vtkMath::UninitializeBounds(this->Bounds);
  bool first = true;
  for (vtkActor* actor : this->GetToolActors()) {
    if (!actor->GetVisibility()) continue;
    const double* b = actor->GetBounds();
    if (!b || !vtkMath::AreBoundsInitialized(b)) continue;
    for (int k = 0; k < 3; ++k) {
      this->Bounds[2 * k] = first ? b[2 * k] : std::min(this->Bounds[2 * k], b[2 * k]);
      this->Bounds[2 * k + 1] = first ? b[2 * k + 1] : std::max(this->Bounds[2 * k + 1], b[2 * k + 1]);
    }
    first = false;
  }
  return this->Bounds;
}

void ToolRepresentation::GetActors(vtkPropCollection* actors) {
  for (vtkActor* actor : this->GetToolActors()) actors->AddItem(actor);
}

void ToolRepresentation::ReleaseGraphicsResources(vtkWindow* window) {
  for (vtkActor* actor : this->GetToolActors()) actor->ReleaseGraphicsResources(window);
}

int ToolRepresentation::RenderOpaqueGeometry(vtkViewport* viewport) {
  // Handles keep their size in pixels: rebuild for the current camera on every frame.
  this->BuildRepresentation();
  int count = 0;
  for (vtkActor* actor : this->GetToolActors())
    if (actor->GetVisibility()) count += actor->RenderOpaqueGeometry(viewport);
  return count;
}

int ToolRepresentation::RenderTranslucentPolygonalGeometry(vtkViewport* viewport) {
  int count = 0;
  for (vtkActor* actor : this->GetToolActors())
    if (actor->GetVisibility() && actor->HasTranslucentPolygonalGeometry())
      count += actor->RenderTranslucentPolygonalGeometry(viewport);
  return count;
}

vtkTypeBool ToolRepresentation::HasTranslucentPolygonalGeometry() {
  // Called before the opaque pass: build so the actors know their opacity.
  this->BuildRepresentation();
  for (vtkActor* actor : this->GetToolActors())
    if (actor->GetVisibility() && actor->HasTranslucentPolygonalGeometry()) return 1;
  return 0;
}

}  // namespace deepcut
