// SPDX-License-Identifier: MIT
// The surface mapper (app/studio/surface_mapper.h) under xvfb-run: its frames equal VTK's own
// mapper's pixel for pixel on a surface with a degenerate triangle, with edges drawn, after its
// cells change (the cell array or only its connectivity marked modified) and after its points
// alone change; its own triangle buffer is what drew (every triangle, the degenerate one too,
// where VTK's leaves that out), VTK's build takes over for edges and its own comes back after.
#include "surface_mapper.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOpenGLIndexBufferObject.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnsignedCharArray.h>

#include <QtTest/QtTest>
#include <cmath>

namespace {

/// The mapper, with the size of the triangle buffer it drew with.
class ProbedMapper : public deepcut::studio::SurfaceMapper {
 public:
  static ProbedMapper* New();
  vtkTypeMacro(ProbedMapper, deepcut::studio::SurfaceMapper)
  std::size_t triangle_indices() const { return Primitives[PrimitiveTris].IBO->IndexCount; }
};
vtkStandardNewMacro(ProbedMapper);

/// An n x n grid of quads in two triangles each, on a wave, and a last triangle that names one
/// point twice (VTK leaves it out of its buffer).
vtkSmartPointer<vtkPolyData> grid(int n) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x)
      points->InsertNextPoint(x / double(n) - 0.5, y / double(n) - 0.5, 0.1 * std::sin(0.7 * x + 0.3 * y));
  const vtkIdType dup = points->InsertNextPoint(0.0, 0.0, 0.2);
  vtkNew<vtkCellArray> polys;
  polys->Use64BitStorage();
  auto id = [n](int x, int y) { return vtkIdType(y * (n + 1) + x); };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      polys->InsertNextCell({id(x, y), id(x + 1, y), id(x + 1, y + 1)});
      polys->InsertNextCell({id(x, y), id(x + 1, y + 1), id(x, y + 1)});
    }
  polys->InsertNextCell({dup, dup, id(n, n)});
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(polys);
  return poly;
}

/// One frame of `poly` drawn by `mapper` (with edges when asked), as RGB bytes.
vtkSmartPointer<vtkUnsignedCharArray> frame(vtkRenderWindow* window, vtkPolyDataMapper* mapper,
                                            vtkPolyData* poly, bool edges) {
  mapper->SetInputData(poly);
  mapper->ScalarVisibilityOff();  // as the studio draws a surface (colours per cell take VTK's build)
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetEdgeVisibility(edges);
  vtkNew<vtkRenderer> renderer;
  renderer->AddActor(actor);
  renderer->GetActiveCamera()->SetPosition(0.3, -1.0, 2.0);
  renderer->ResetCamera();
  window->AddRenderer(renderer);
  window->Render();
  auto pixels = vtkSmartPointer<vtkUnsignedCharArray>::New();
  window->GetPixelData(0, 0, 159, 159, 1, pixels);
  window->RemoveRenderer(renderer);
  return pixels;
}

bool same(vtkUnsignedCharArray* a, vtkUnsignedCharArray* b) {
  if (a->GetNumberOfValues() != b->GetNumberOfValues()) return false;
  return std::equal(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues(), b->GetPointer(0));
}

}  // namespace

class SurfaceMapperTest : public QObject {
  Q_OBJECT

 private slots:
  void frames_equal_vtks_own_mapper_and_follow_every_change();
};

void SurfaceMapperTest::frames_equal_vtks_own_mapper_and_follow_every_change() {
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(160, 160);
  vtkSmartPointer<vtkPolyData> poly = grid(12);
  const vtkIdType cells = poly->GetNumberOfCells();
  vtkNew<ProbedMapper> ours;
  vtkNew<vtkPolyDataMapper> theirs;
  auto check = [&](bool edges) {
    vtkSmartPointer<vtkUnsignedCharArray> a = frame(window, ours, poly, edges);
    vtkSmartPointer<vtkUnsignedCharArray> b = frame(window, theirs, poly, edges);
    QVERIFY(same(a, b));
  };
  check(false);
  QCOMPARE(ours->triangle_indices(), std::size_t(3 * cells));  // VTK's own: 3 * (cells - 1)

  // Edges: VTK's own build (which leaves the degenerate triangle out), then the mapper's again.
  check(true);
  QCOMPARE(ours->triangle_indices(), std::size_t(3 * (cells - 1)));
  check(false);
  QCOMPARE(ours->triangle_indices(), std::size_t(3 * cells));

  // Fewer cells (what a step does to the view's cells): the buffer follows.
  poly->GetPolys()->GetOffsetsArray64()->SetNumberOfValues(cells);  // the last cell dropped
  poly->GetPolys()->GetConnectivityArray64()->SetNumberOfValues(3 * (cells - 1));
  poly->GetPolys()->Modified();
  check(false);
  QCOMPARE(ours->triangle_indices(), std::size_t(3 * (cells - 1)));

  // A cell rewritten with only its connectivity array marked modified: the frame follows it.
  vtkTypeInt64Array* connectivity = poly->GetPolys()->GetConnectivityArray64();
  for (int k = 0; k < 3; ++k) connectivity->SetValue(3 * (cells / 2) + k, 0);
  connectivity->Modified();
  check(false);

  // New positions only (a pose): the frame follows them.
  vtkFloatArray* xyz = vtkFloatArray::SafeDownCast(poly->GetPoints()->GetData());
  for (vtkIdType i = 0; i < xyz->GetNumberOfTuples(); ++i) xyz->SetComponent(i, 2, -xyz->GetComponent(i, 2));
  poly->GetPoints()->Modified();
  check(false);
}

QTEST_APPLESS_MAIN(SurfaceMapperTest)
#include "surface_mapper_test.moc"
