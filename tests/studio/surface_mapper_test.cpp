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
#include <array>
#include <cmath>
#include <string>

#include "offscreen_frames.h"

namespace {

using deepcut::test::studio::frame_of;
using deepcut::test::studio::offscreen_window;
using deepcut::test::studio::same_pixels;

/// The mapper, with the size of the triangle buffer it drew with.
class ProbedMapper : public deepcut::studio::SurfaceMapper {
 public:
  static ProbedMapper* New();
  vtkTypeMacro(ProbedMapper, deepcut::studio::SurfaceMapper)
  std::size_t triangle_indices() const { return Primitives[PrimitiveTris].IBO->IndexCount; }
  bool mapped() const { return last_mapped_; }
  void map_uploads(bool map) { map_uploads_ = map; }
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

/// One actor and renderer kept across frames (VTK keeps its index buffers' state with the mapper).
struct Kept {
  vtkNew<vtkActor> actor;
  vtkNew<vtkRenderer> renderer;
  Kept(vtkPolyDataMapper* mapper, vtkPolyData* poly) {
    mapper->SetInputData(poly);
    mapper->ScalarVisibilityOff();  // as the studio draws a surface (colours per cell take VTK's build)
    actor->SetMapper(mapper);
    renderer->AddActor(actor);
    renderer->GetActiveCamera()->SetPosition(0.3, -1.0, 2.0);
    renderer->ResetCamera();
  }
  vtkSmartPointer<vtkUnsignedCharArray> frame(vtkRenderWindow* window, int representation) {
    actor->GetProperty()->SetRepresentation(representation);
    return frame_of(window, renderer);
  }
};

/// One frame of `poly` drawn by `mapper` through a new actor (with edges when asked), as RGB bytes.
vtkSmartPointer<vtkUnsignedCharArray> frame(vtkRenderWindow* window, vtkPolyDataMapper* mapper,
                                            vtkPolyData* poly, bool edges) {
  Kept kept(mapper, poly);
  kept.actor->GetProperty()->SetEdgeVisibility(edges);
  return kept.frame(window, VTK_SURFACE);
}

}  // namespace

class SurfaceMapperTest : public QObject {
  Q_OBJECT

 private slots:
  void frames_equal_vtks_own_mapper_and_follow_every_change();
  void one_actor_switching_representations_draws_as_vtk_does();
  void cells_other_than_triangles_take_vtks_build();
  void an_upload_without_mapping_draws_the_same();

 private:
  vtkSmartPointer<vtkRenderWindow> window_ = offscreen_window(160, 160);  // for every case
};

void SurfaceMapperTest::frames_equal_vtks_own_mapper_and_follow_every_change() {
  vtkRenderWindow* window = window_;
  vtkSmartPointer<vtkPolyData> poly = grid(12);
  const vtkIdType cells = poly->GetNumberOfCells();
  vtkNew<ProbedMapper> ours;
  vtkNew<vtkPolyDataMapper> theirs;
  auto check = [&](bool edges) {
    vtkSmartPointer<vtkUnsignedCharArray> a = frame(window, ours, poly, edges);
    vtkSmartPointer<vtkUnsignedCharArray> b = frame(window, theirs, poly, edges);
    QVERIFY(same_pixels(a, b));
  };
  check(false);
  QCOMPARE(ours->triangle_indices(), std::size_t(3 * cells));  // VTK's own: 3 * (cells - 1)
  QVERIFY2(ours->mapped(), "the buffer was written mapped (Mesa maps index buffers)");

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

void SurfaceMapperTest::one_actor_switching_representations_draws_as_vtk_does() {
  // Surface, wireframe, surface, wireframe again (nothing else changed), points, surface: VTK's
  // build must not take the mapper's triangle buffer for its own line or point buffers.
  vtkRenderWindow* window = window_;
  vtkSmartPointer<vtkPolyData> poly = grid(12);
  vtkNew<ProbedMapper> ours;
  vtkNew<vtkPolyDataMapper> theirs;
  Kept a(ours, poly), b(theirs, poly);
  for (int representation : {VTK_SURFACE, VTK_WIREFRAME, VTK_SURFACE, VTK_WIREFRAME, VTK_POINTS, VTK_SURFACE}) {
    vtkSmartPointer<vtkUnsignedCharArray> x = a.frame(window, representation);
    vtkSmartPointer<vtkUnsignedCharArray> y = b.frame(window, representation);
    QVERIFY2(same_pixels(x, y), ("representation " + std::to_string(representation)).c_str());
  }
  QCOMPARE(ours->triangle_indices(), std::size_t(3 * poly->GetNumberOfCells()));  // its own again
}

void SurfaceMapperTest::cells_other_than_triangles_take_vtks_build() {
  // A quad and a two-point cell: three ids per cell on average, but not triangles (read as
  // triangles they would draw (0, 1, 2) and (3, 4, 5), the second where VTK draws nothing).
  vtkRenderWindow* window = window_;
  vtkNew<vtkPoints> points;
  for (const auto& p : {std::array<double, 3>{-0.5, -0.5, 0.0}, {0.5, -0.5, 0.1}, {0.5, 0.5, 0.0}, {-0.5, 0.5, 0.1}, {0.9, 0.9, 0.0}, {-0.9, 0.9, 0.0}})
    points->InsertNextPoint(p.data());
  vtkNew<vtkCellArray> polys;
  polys->InsertNextCell({0, 1, 2, 3});
  polys->InsertNextCell({4, 5});
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(polys);
  vtkNew<ProbedMapper> ours;
  vtkNew<vtkPolyDataMapper> theirs;
  vtkSmartPointer<vtkUnsignedCharArray> x = frame(window, ours, poly, false);
  vtkSmartPointer<vtkUnsignedCharArray> y = frame(window, theirs, poly, false);
  QVERIFY(same_pixels(x, y));
  QCOMPARE(ours->triangle_indices(), std::size_t(6));  // the quad's two triangles, VTK's build
}

void SurfaceMapperTest::an_upload_without_mapping_draws_the_same() {
  // The path taken where a driver does not map the buffer: an array narrowed, then uploaded.
  vtkRenderWindow* window = window_;
  vtkSmartPointer<vtkPolyData> poly = grid(12);
  vtkNew<ProbedMapper> ours;
  ours->map_uploads(false);
  vtkNew<vtkPolyDataMapper> theirs;
  vtkSmartPointer<vtkUnsignedCharArray> x = frame(window, ours, poly, false);
  vtkSmartPointer<vtkUnsignedCharArray> y = frame(window, theirs, poly, false);
  QVERIFY(same_pixels(x, y));
  QVERIFY(!ours->mapped());
  QCOMPARE(ours->triangle_indices(), std::size_t(3 * poly->GetNumberOfCells()));
}

QTEST_APPLESS_MAIN(SurfaceMapperTest)
#include "surface_mapper_test.moc"
