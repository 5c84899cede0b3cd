// SPDX-License-Identifier: MIT
#include "instance_data.h"

#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkMath.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkTexture.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "deepcut/core/posed_corner_normal.h"
#include "deepcut/core/smallest_fit.h"
#include "deepcut/widgets/texture.h"
#include "surface_mapper.h"

namespace deepcut::studio {

MaterialLook instance_look(const plugins::Scene& scene, const plugins::SceneInstance& sp) {
  const Model& model = *scene.model;
  return material_look(model, model.meshes[static_cast<std::size_t>(sp.mesh)]
                                  .primitives[static_cast<std::size_t>(sp.primitive)]
                                  .material);
}

void use_texture_coords(vtkPolyData* poly, bool use) {
  vtkPointData* pd = poly->GetPointData();
  vtkDataArray* uv = pd->GetArray("uv0");
  vtkDataArray* active = pd->GetTCoords();
  if (use && uv && active != uv)
    pd->SetActiveTCoords("uv0");
  else if (!use && active)
    pd->SetActiveAttribute(-1, vtkDataSetAttributes::TCOORDS);
}

std::shared_ptr<ViewPolyData> instance_view_data(const plugins::Scene& scene,
                                                 const plugins::SceneInstance& sp) {
  std::shared_ptr<ViewPolyData> data;
  // Without the scene's corner normals (an open's scene, before its first frame): each drawn
  // point's posed normal, computed alone (the same bits).
  const CornerNormalPoser poser(*sp.pose, *sp.surface);
  if (sp.posed_normals.empty() && poser.has_normals())
    data = std::make_shared<ViewPolyData>(*sp.surface, sp.posed(), poser);
  else
    data = std::make_shared<ViewPolyData>(*sp.surface, sp.posed(), &sp.posed_normals);
  const MaterialLook look = instance_look(scene, sp);
  use_texture_coords(data->poly(), look.base_color_image >= 0 && look.texcoord == 0);
  return data;
}

std::shared_ptr<ViewPolyData> instance_view_data(const plugins::Scene& scene,
                                                 const plugins::SceneInstance& sp, const ViewPolyData& source,
                                                 const PrimitiveOrigin& origin,
                                                 std::vector<std::shared_ptr<ViewPolyData>>* spare,
                                                 ViewPolyData::CopyScratch* scratch) {
  std::shared_ptr<ViewPolyData> taken;
  if (spare)
    taken = take_smallest_fit(*spare, sp.surface->face_slots(),
                              [](const std::shared_ptr<ViewPolyData>& data) { return ViewPolyData::room(*data); });
  auto data = std::make_shared<ViewPolyData>(*sp.surface, sp.posed(), &sp.posed_normals, source, origin,
                                             taken.get(), scratch);
  const MaterialLook look = instance_look(scene, sp);
  use_texture_coords(data->poly(), look.base_color_image >= 0 && look.texcoord == 0);
  return data;
}

void compute_draw_caches(const ViewPolyData& data) {
  vtkPolyData* poly = data.poly();
  vtkDataArray* points = poly->GetPoints()->GetData();
  double bounds[6];
  for (int k = 0; k < 3; ++k) points->GetRange(bounds + 2 * k, k);
  // A full build's corner points are each made for a corner of a live face, and a deleted
  // face's cell names point 0 (then made too): every point is some cell's, so the cells' bounds
  // are the coordinates' ranges, known now, kept for the surface mapper (its bounds while the
  // points and cells are unchanged) in place of VTK's pass over every cell's point ids.
  // Otherwise (a point per vertex slot, some perhaps unused) VTK's own, cached in the data.
  // The one caller (SceneView::prepare) passes a full build (instance_view_data without a
  // source), with at least one cell and point: the guards hold there and are for other callers.
  if (data.corner_points() && !data.copied() && poly->GetNumberOfCells() > 0 && poly->GetNumberOfPoints() > 0)
    SurfaceMapper::keep_cells_bounds(poly, bounds);
  else
    poly->GetCellsBounds(bounds);
}

vtkSmartPointer<vtkPolyData> normal_lines(const std::vector<vtkPolyData*>& drawn, float length) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  vtkNew<vtkCellArray> lines;
  std::size_t total = 0;
  for (vtkPolyData* poly : drawn) total += static_cast<std::size_t>(poly->GetNumberOfPoints());
  // Big meshes: draw every k-th normal so the view stays readable and responsive.
  const std::size_t stride = std::max<std::size_t>(1, total / 60000);
  auto add_line = [&](const double p[3], const double d[3]) {
    const vtkIdType a = points->InsertNextPoint(p);
    const vtkIdType b =
        points->InsertNextPoint(p[0] + length * d[0], p[1] + length * d[1], p[2] + length * d[2]);
    const vtkIdType ids[2] = {a, b};
    lines->InsertNextCell(2, ids);
  };
  for (vtkPolyData* instance : drawn) {
    vtkDataArray* n = instance->GetPointData()->GetNormals();
    if (n) {
      for (vtkIdType i = 0; i < instance->GetNumberOfPoints(); i += static_cast<vtkIdType>(stride)) {
        double p[3], d[3];
        instance->GetPoint(i, p);
        n->GetTuple(i, d);
        add_line(p, d);
      }
      continue;
    }
    // No normals in the file: show the face normals (what the renderer shades with) at the
    // face centres.
    vtkCellArray* polys = instance->GetPolys();
    vtkIdType npts = 0;
    const vtkIdType* ids = nullptr;
    vtkIdType cell = 0;
    for (polys->InitTraversal(); polys->GetNextCell(npts, ids); ++cell) {
      if (npts != 3 || cell % static_cast<vtkIdType>(stride) != 0) continue;
      double a[3], b[3], c[3];
      instance->GetPoint(ids[0], a);
      instance->GetPoint(ids[1], b);
      instance->GetPoint(ids[2], c);
      const glm::dvec3 pa(a[0], a[1], a[2]), pb(b[0], b[1], b[2]), pc(c[0], c[1], c[2]);
      const glm::dvec3 cross = glm::cross(pb - pa, pc - pa);
      if (glm::length(cross) <= 0.0) continue;
      const glm::dvec3 centre = (pa + pb + pc) / 3.0, normal = glm::normalize(cross);
      const double p[3] = {centre.x, centre.y, centre.z}, d[3] = {normal.x, normal.y, normal.z};
      add_line(p, d);
    }
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetLines(lines);
  return poly;
}

vtkSmartPointer<vtkPolyData> stand_in_triangle(vtkCamera* camera, bool textured) {
  glm::dvec3 focus, up, direction;
  camera->GetFocalPoint(&focus.x);
  camera->GetViewUp(&up.x);
  camera->GetDirectionOfProjection(&direction.x);
  const double half =
      camera->GetDistance() * std::tan(0.5 * vtkMath::RadiansFromDegrees(camera->GetViewAngle()));
  const glm::dvec3 right = glm::cross(direction, up) * (0.75 * half), upward = up * (0.375 * half);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  for (const glm::dvec3& p : {focus - right - upward, focus + right - upward, focus + 2.0 * upward})
    points->InsertNextPoint(p.x, p.y, p.z);
  vtkNew<vtkFloatArray> normals, uv;
  normals->SetNumberOfComponents(3);
  uv->SetNumberOfComponents(2);
  for (int k = 0; k < 3; ++k) {
    normals->InsertNextTuple3(-direction.x, -direction.y, -direction.z);
    uv->InsertNextTuple2(0.5 * k, 0.5);
  }
  const vtkIdType ids[3] = {0, 1, 2};
  vtkNew<vtkCellArray> cells;
  cells->InsertNextCell(3, ids);
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(cells);
  poly->GetPointData()->SetNormals(normals);
  if (textured) poly->GetPointData()->SetTCoords(uv);
  return poly;
}

vtkSmartPointer<vtkTexture> stand_in_texture() {
  static const std::vector<unsigned char> kOnePixelPng = {
      0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
      0x44, 0x52, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x02, 0x00, 0x00,
      0x00, 0x90, 0x77, 0x53, 0xde, 0x00, 0x00, 0x00, 0x0c, 0x49, 0x44, 0x41, 0x54, 0x78,
      0x9c, 0x63, 0x38, 0x71, 0xe2, 0x04, 0x00, 0x04, 0xb4, 0x02, 0x59, 0x16, 0x2e, 0x81,
      0x40, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  return make_texture({"stand-in", "image/png", kOnePixelPng});
}

Overlay stand_in_skeleton(vtkCamera* camera) {
  glm::dvec3 focus, up;
  camera->GetFocalPoint(&focus.x);
  camera->GetViewUp(&up.x);
  const double half = camera->GetDistance() * std::tan(0.5 * vtkMath::RadiansFromDegrees(camera->GetViewAngle()));
  const glm::dvec3 top = focus + up * (0.5 * half);
  OverlayLines bones;  // as skeleton_overlay's
  bones.width_px = 3.0f;
  bones.on_top = true;
  bones.endpoints = {glm::vec3(focus), glm::vec3(top)};
  OverlayPoints joints;
  joints.size_px = 7.0f;
  joints.on_top = true;
  joints.positions = {glm::vec3(focus)};
  Overlay overlay;
  overlay.lines.push_back(std::move(bones));
  overlay.points.push_back(std::move(joints));
  return overlay;
}

}  // namespace deepcut::studio
