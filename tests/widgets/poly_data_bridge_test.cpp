// SPDX-License-Identifier: MIT
#include "deepcut/widgets/poly_data_bridge.h"

#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>

#include "deepcut/core/adjacency.h"
#include "fixtures.h"

namespace deepcut {

TEST(PolyDataBridgeTest, split_corners_duplicates_seam_points_only) {
  const SurfaceMesh mesh = test::make_grid(2, 2);  // 9 vertices, a UV seam of 3 vertices at x = 0.5
  const auto poly = to_poly_data(mesh);
  EXPECT_EQ(poly->GetNumberOfPolys(), 8);
  EXPECT_EQ(poly->GetNumberOfPoints(), 12);  // 9 + 3 seam copies
  ASSERT_NE(poly->GetPointData()->GetTCoords(), nullptr);
  ASSERT_NE(poly->GetPointData()->GetArray("weights0"), nullptr);
  ASSERT_NE(poly->GetCellData()->GetArray("face_id"), nullptr);
  PolyDataOptions welded;
  welded.split_corners = false;
  EXPECT_EQ(to_poly_data(mesh, welded)->GetNumberOfPoints(), 9);
}

TEST(PolyDataBridgeTest, round_trip_keeps_topology_and_geometry) {
  const SurfaceMesh tube = test::make_tube(10, 3);
  PolyDataOptions welded;
  welded.split_corners = false;
  const SurfaceMesh back = from_poly_data(to_poly_data(tube, welded));
  EXPECT_EQ(back.face_count(), tube.face_count());
  EXPECT_NEAR(back.volume(), tube.volume(), 1e-5);
  EXPECT_TRUE(Adjacency::build(back).boundary_edges().empty());
}

}  // namespace deepcut
