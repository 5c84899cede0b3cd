// SPDX-License-Identifier: MIT
// The draw caches of a prepared view (instance_data.h, compute_draw_caches) and the surface
// mapper's bounds (surface_mapper.h): a full corner-point build's cell bounds are kept with the
// data and are the mapper's bounds, without VTK's pass over the cells (cells hidden from such a
// pass do not change them), while the points and cells are unchanged; they equal what VTK computes
// over the points the cells use (a vertex without a live face, every face deleted, a new pose).
// No window: runs without a display.
#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <QtTest/QtTest>
#include <algorithm>
#include <vector>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/mesh_editor.h"
#include "instance_data.h"
#include "surface_mapper.h"

namespace {

using deepcut::studio::SurfaceMapper;

/// What VTK computes as the cells' bounds of a copy of `poly` (no bounds kept with it).
void vtk_cells_bounds(vtkPolyData* poly, double out[6]) {
  auto fresh = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->DeepCopy(poly->GetPoints());
  fresh->SetPoints(points);
  vtkNew<vtkCellArray> cells;
  cells->DeepCopy(poly->GetPolys());
  fresh->SetPolys(cells);
  fresh->GetCellsBounds(out);
}

/// The bounds a surface mapper drawing `poly` takes.
void mapper_bounds(vtkPolyData* poly, double out[6]) {
  vtkNew<SurfaceMapper> mapper;
  mapper->SetInputData(poly);
  mapper->GetBounds(out);
}

/// Makes every cell of `poly` name its point 0 behind VTK's back (nothing marked modified): a pass
/// over the cells from now on finds point 0's box alone, while bounds kept with the data still
/// hold. Bounds other than point 0's box then show that no pass over the cells made them.
void hide_cells(vtkPolyData* poly) {
  vtkDataArray* ids = poly->GetPolys()->GetConnectivityArray();
  for (vtkIdType i = 0; i < ids->GetNumberOfTuples(); ++i) ids->SetComponent(i, 0, 0.0);
}

// The bounds of `data` through VTK's own pass over a copy (`computed`), then, with its cells
// hidden (hide_cells), its caches made and its bounds through the mapper (`got`): equal only if
// neither the caches nor the mapper passed over the cells. `data`'s cells are spent afterwards.
void cached_bounds(deepcut::ViewPolyData& data, double got[6], double computed[6]) {
  vtk_cells_bounds(data.poly(), computed);
  hide_cells(data.poly());
  deepcut::studio::compute_draw_caches(data);
  mapper_bounds(data.poly(), got);
}

deepcut::Model cactus() {
  deepcut::CactusOptions options;
  options.target_triangles = 3000;
  return deepcut::make_cactus(options);
}

}  // namespace

class DrawCachesTest : public QObject {
  Q_OBJECT

 private slots:
  void kept_cell_bounds_are_the_mappers_without_vtks_pass();
  void kept_cell_bounds_equal_vtks_at_rest_and_moved();
  void a_vertex_without_faces_is_left_out();
  void every_face_deleted();
  void a_new_pose_after_the_caches_gives_its_bounds();
};

void DrawCachesTest::kept_cell_bounds_are_the_mappers_without_vtks_pass() {
  // Bounds kept that differ from the data's: the mapper returns them, so they were used.
  const deepcut::Model model = cactus();
  const deepcut::SurfaceMesh& mesh = model.meshes.at(0).primitives.at(0).mesh;
  deepcut::ViewPolyData data(mesh, mesh.positions());
  const double kept[6] = {-100, 100, -200, 200, -300, 300};
  SurfaceMapper::keep_cells_bounds(data.poly(), kept);
  double got[6];
  mapper_bounds(data.poly(), got);
  for (int k = 0; k < 6; ++k) QCOMPARE(got[k], kept[k]);
  // The points changed since: VTK's pass, the true bounds.
  data.poly()->GetPoints()->Modified();
  double computed[6];
  vtk_cells_bounds(data.poly(), computed);
  mapper_bounds(data.poly(), got);
  for (int k = 0; k < 6; ++k) QCOMPARE(got[k], computed[k]);
}

void DrawCachesTest::kept_cell_bounds_equal_vtks_at_rest_and_moved() {
  const deepcut::Model model = cactus();
  const deepcut::SurfaceMesh& mesh = model.meshes.at(0).primitives.at(0).mesh;
  std::vector<glm::vec3> moved = mesh.positions();
  for (glm::vec3& p : moved) p = p * 1.5f + glm::vec3(-2.0f, 0.25f, 7.0f);
  const std::vector<glm::vec3>* const poses[] = {&mesh.positions(), &moved};
  for (const std::vector<glm::vec3>* positions : poses) {
    deepcut::ViewPolyData data(mesh, *positions);
    QVERIFY(data.corner_points());
    double got[6], computed[6];
    cached_bounds(data, got, computed);
    QVERIFY(std::equal(got, got + 6, computed));
  }
}

void DrawCachesTest::a_vertex_without_faces_is_left_out() {
  // The vertex of largest x moved further out, then the faces around it deleted: it has no point,
  // and the bounds' largest x is another vertex's.
  deepcut::Model model = cactus();
  deepcut::SurfaceMesh& mesh = model.meshes.at(0).primitives.at(0).mesh;
  std::uint32_t extreme = 0;
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.positions()[v].x > mesh.positions()[extreme].x) extreme = v;
  deepcut::MeshEditor editor(mesh);
  for (std::uint32_t f = 0; f < mesh.face_slots(); ++f) {
    const deepcut::Triangle& t = mesh.face(deepcut::FaceId(f));
    if (t[0].index == extreme || t[1].index == extreme || t[2].index == extreme)
      editor.remove_face(deepcut::FaceId(f));
  }
  std::vector<glm::vec3> positions = mesh.positions();
  positions[extreme].x += 10.0f;
  deepcut::ViewPolyData data(mesh, positions);
  QVERIFY(data.corner_points());
  double got[6], computed[6];
  cached_bounds(data, got, computed);
  QVERIFY(std::equal(got, got + 6, computed));
  QVERIFY(got[1] < static_cast<double>(mesh.positions()[extreme].x) + 1.0);
}

void DrawCachesTest::every_face_deleted() {
  deepcut::Model model = cactus();
  deepcut::SurfaceMesh& mesh = model.meshes.at(0).primitives.at(0).mesh;
  deepcut::MeshEditor editor(mesh);
  for (std::uint32_t f = 0; f < mesh.face_slots(); ++f) editor.remove_face(deepcut::FaceId(f));
  deepcut::ViewPolyData data(mesh, mesh.positions());
  double got[6], computed[6];
  cached_bounds(data, got, computed);
  QVERIFY(std::equal(got, got + 6, computed));
}

void DrawCachesTest::a_new_pose_after_the_caches_gives_its_bounds() {
  const deepcut::Model model = cactus();
  const deepcut::SurfaceMesh& mesh = model.meshes.at(0).primitives.at(0).mesh;
  deepcut::ViewPolyData data(mesh, mesh.positions());
  deepcut::studio::compute_draw_caches(data);
  std::vector<glm::vec3> larger = mesh.positions();
  for (glm::vec3& p : larger) p = p * 3.0f + glm::vec3(5.0f, -1.0f, 2.0f);
  data.set_positions(larger, nullptr);
  double got[6], computed[6];
  mapper_bounds(data.poly(), got);
  vtk_cells_bounds(data.poly(), computed);
  for (int k = 0; k < 6; ++k) QCOMPARE(got[k], computed[k]);
  double rest[6];
  const deepcut::ViewPolyData at_rest(mesh, mesh.positions());
  vtk_cells_bounds(at_rest.poly(), rest);
  QVERIFY(got[1] > rest[1]);
}

QTEST_APPLESS_MAIN(DrawCachesTest)
#include "draw_caches_test.moc"
