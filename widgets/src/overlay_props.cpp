// SPDX-License-Identifier: MIT
#include "deepcut/widgets/overlay_props.h"

#include <vtkActor.h>
#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkGlyph3DMapper.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkScalarBarActor.h>
#include <vtkSphereSource.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>

namespace deepcut {
namespace {

unsigned char to_byte(float c) {
  return static_cast<unsigned char>(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f));
}

vtkSmartPointer<vtkPoints> make_points(const std::vector<glm::vec3>& positions) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(static_cast<vtkIdType>(positions.size()));
  for (std::size_t i = 0; i < positions.size(); ++i)
    points->SetPoint(static_cast<vtkIdType>(i), positions[i].x, positions[i].y, positions[i].z);
  return points;
}

/// Per-point RGB colours, or nullptr when `colors` does not match the point count.
vtkSmartPointer<vtkUnsignedCharArray> make_colors(const std::vector<glm::vec3>& colors, std::size_t count) {
  if (colors.size() != count || count == 0) return nullptr;
  auto array = vtkSmartPointer<vtkUnsignedCharArray>::New();
  array->SetName("colors");
  array->SetNumberOfComponents(3);
  array->SetNumberOfTuples(static_cast<vtkIdType>(count));
  for (std::size_t i = 0; i < count; ++i) {
    const unsigned char rgb[3] = {to_byte(colors[i].r), to_byte(colors[i].g), to_byte(colors[i].b)};
    array->SetTypedTuple(static_cast<vtkIdType>(i), rgb);
  }
  return array;
}

vtkSmartPointer<vtkActor> make_actor(vtkPolyData* poly, bool has_colors, const glm::vec3& color) {
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  mapper->SetScalarVisibility(has_colors);
  mapper->SetColorModeToDirectScalars();
  mapper->SetScalarModeToUsePointData();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(color.r, color.g, color.b);
  actor->PickableOff();
  return actor;
}

// Point set `set` as points drawn as spheres of its pixel size.
vtkSmartPointer<vtkActor> points_actor(const OverlayPoints& set) {
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(make_points(set.positions));
  vtkNew<vtkCellArray> verts;
  for (vtkIdType i = 0; i < static_cast<vtkIdType>(set.positions.size()); ++i) verts->InsertNextCell(1, &i);
  poly->SetVerts(verts);
  const auto colors = make_colors(set.colors, set.positions.size());
  if (colors) poly->GetPointData()->SetScalars(colors);
  auto actor = make_actor(poly, colors != nullptr, set.color);
  actor->GetProperty()->SetPointSize(set.size_px);
  actor->GetProperty()->RenderPointsAsSpheresOn();
  actor->GetProperty()->SetSpecular(0.3);
  return actor;
}

// Line set `set` as segments of its pixel width (drawn as tubes when `line_tubes`).
vtkSmartPointer<vtkActor> lines_actor(const OverlayLines& set, bool line_tubes) {
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(make_points(set.endpoints));
  vtkNew<vtkCellArray> lines;
  for (vtkIdType i = 0; i + 1 < static_cast<vtkIdType>(set.endpoints.size()); i += 2) {
    const vtkIdType ids[2] = {i, i + 1};
    lines->InsertNextCell(2, ids);
  }
  poly->SetLines(lines);
  auto actor = make_actor(poly, false, set.color);
  actor->GetProperty()->SetLineWidth(set.width_px);
  if (line_tubes) actor->GetProperty()->RenderLinesAsTubesOn();
  return actor;
}

// Sphere set `set`: a unit sphere glyph at each centre, scaled by its radius.
vtkSmartPointer<vtkActor> spheres_actor(const OverlaySpheres& set) {
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(make_points(set.centers));
  vtkNew<vtkFloatArray> radius;
  radius->SetName("radius");
  radius->SetNumberOfValues(static_cast<vtkIdType>(set.radii.size()));
  for (std::size_t i = 0; i < set.radii.size(); ++i)
    radius->SetValue(static_cast<vtkIdType>(i), set.radii[i]);
  poly->GetPointData()->AddArray(radius);
  const auto colors = make_colors(set.colors, set.centers.size());
  if (colors) poly->GetPointData()->SetScalars(colors);
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(1.0);
  sphere->SetThetaResolution(20);
  sphere->SetPhiResolution(14);
  vtkNew<vtkGlyph3DMapper> mapper;
  mapper->SetInputData(poly);
  mapper->SetSourceConnection(sphere->GetOutputPort());
  mapper->SetScaleArray("radius");
  mapper->SetScaleModeToScaleByMagnitude();
  mapper->ScalingOn();
  mapper->SetScalarVisibility(colors != nullptr);
  mapper->SetColorModeToDirectScalars();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(set.color.r, set.color.g, set.color.b);
  actor->GetProperty()->SetOpacity(set.opacity);
  actor->PickableOff();
  return actor;
}

}  // namespace

OverlayProps make_overlay_props(const Overlay& overlay, bool line_tubes) {
  OverlayProps props;
  for (const OverlayPoints& set : overlay.points)
    if (!set.positions.empty()) (set.on_top ? props.on_top : props.depth_tested).push_back(points_actor(set));
  for (const OverlayLines& set : overlay.lines)
    if (set.endpoints.size() >= 2)
      (set.on_top ? props.on_top : props.depth_tested).push_back(lines_actor(set, line_tubes));
  for (const OverlaySpheres& set : overlay.spheres)
    if (!set.centers.empty() && set.radii.size() == set.centers.size())
      props.depth_tested.push_back(spheres_actor(set));
  return props;
}

vtkSmartPointer<vtkProp> make_color_bar(const ColorBar& bar) {
  std::vector<glm::vec3> stops = bar.stops;
  if (stops.size() < 2) stops = {glm::vec3(0.0f), glm::vec3(1.0f)};
  vtkNew<vtkLookupTable> table;
  const int n = 256;
  table->SetNumberOfTableValues(n);
  table->SetRange(bar.min, bar.max);
  for (int i = 0; i < n; ++i) {
    const float s = static_cast<float>(i) / (n - 1) * static_cast<float>(stops.size() - 1);
    const auto k = std::min(static_cast<std::size_t>(s), stops.size() - 2);
    const glm::vec3 c = glm::mix(stops[k], stops[k + 1], s - static_cast<float>(k));
    table->SetTableValue(i, c.r, c.g, c.b, 1.0);
  }
  table->Build();
  auto actor = vtkSmartPointer<vtkScalarBarActor>::New();
  actor->SetLookupTable(table);
  actor->SetTitle(bar.title.c_str());
  actor->SetNumberOfLabels(5);
  actor->SetLabelFormat("%.2f");
  actor->SetMaximumWidthInPixels(90);
  actor->SetMaximumHeightInPixels(320);
  actor->SetBarRatio(0.25);
  actor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  actor->GetPositionCoordinate()->SetValue(0.9, 0.08);
  actor->SetWidth(0.09);
  actor->SetHeight(0.42);
  for (vtkTextProperty* text : {actor->GetTitleTextProperty(), actor->GetLabelTextProperty()}) {
    text->SetColor(0.92, 0.92, 0.92);
    text->SetFontFamilyToArial();
    text->ShadowOff();
    text->ItalicOff();
    text->SetBold(text == actor->GetTitleTextProperty());
    text->SetFontSize(13);
  }
  actor->UnconstrainedFontSizeOn();
  return actor;
}

}  // namespace deepcut
