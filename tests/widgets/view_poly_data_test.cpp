// SPDX-License-Identifier: MIT
// ViewPolyData: the whole build links every corner to its vertex in parallel by vertex ranges;
// a step that moves every vertex then rewrites all their corners. Checked against a fresh build
// at the moved positions, for several thread counts.
#include "deepcut/widgets/view_poly_data.h"

#include <gtest/gtest.h>
#include <vtkFloatArray.h>
#include <vtkPoints.h>

#include <vector>

#include "deepcut/core/parallel.h"
#include "fixtures.h"

namespace deepcut {
namespace {

std::vector<float> points_of(const ViewPolyData& data) {
  auto* a = vtkFloatArray::SafeDownCast(data.poly()->GetPoints()->GetData());
  return std::vector<float>(a->GetPointer(0), a->GetPointer(0) + 3 * a->GetNumberOfTuples());
}

}  // namespace

TEST(ViewPolyDataTest, moved_vertices_rewrite_their_corners_whatever_the_thread_count) {
  const SurfaceMesh mesh = test::make_grid(120, 120);  // 28,800 faces: several link tasks
  std::vector<glm::vec3> moved = mesh.positions();
  PrimitiveChange change;
  change.vertices_before = mesh.vertex_count();
  change.faces_before = mesh.face_slots();
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    moved[v] += glm::vec3(0.0f, 0.0f, 1.0f + static_cast<float>(v));
    change.vertices.push_back(VertexId(v));
  }
  const std::size_t saved = thread_count();
  set_thread_count(1);
  const std::vector<float> expected = points_of(ViewPolyData(mesh, moved));
  for (std::size_t threads : {1, 2, 3, 8}) {
    set_thread_count(threads);
    ViewPolyData data(mesh, mesh.positions());
    ASSERT_TRUE(data.corner_points());
    data.update(mesh, moved, nullptr, change);
    EXPECT_EQ(points_of(data), expected) << threads << " threads";
  }
  set_thread_count(saved);
}

}  // namespace deepcut
