// SPDX-License-Identifier: MIT
#pragma once
// The check the ViewPolyData tests share: data equal to a fresh build of the same mesh,
// positions and normals (as many points, every corner of a live face drawn alike, face ids per
// cell, the corners of a vertex that draw alike sharing one point).

#include <gtest/gtest.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkTypeInt64Array.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "deepcut/core/surface_mesh.h"
#include "deepcut/widgets/view_poly_data.h"

namespace deepcut {

using Normals = std::vector<glm::vec3>;

// Points a full sharing needs: per vertex, the distinct ways its live corners draw (uv, drawn
// normal and the mesh's normal, bit for bit); one point when no face is live.
inline std::size_t distinct_ways(const SurfaceMesh& mesh, const Normals* posed) {
  const auto* uv = mesh.corner_attrs().find<glm::vec2>(attr::kUv0);
  const auto* own = mesh.corner_attrs().find<glm::vec3>(attr::kNormal);
  std::set<std::array<std::uint32_t, 9>> ways;
  for (std::uint32_t f = 0; f < mesh.face_slots(); ++f) {
    if (mesh.is_deleted(FaceId(f))) continue;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t c = SurfaceMesh::corner(FaceId(f), k);
      std::array<std::uint32_t, 9> key{};
      key[0] = mesh.face(FaceId(f))[k].index;
      if (uv) std::memcpy(&key[1], &(*uv)[c], sizeof(glm::vec2));
      if (own) std::memcpy(&key[3], &(*own)[c], sizeof(glm::vec3));
      if (posed && !posed->empty()) std::memcpy(&key[6], &(*posed)[c], sizeof(glm::vec3));
      ways.insert(key);
    }
  }
  return std::max<std::size_t>(ways.size(), 1);
}

inline vtkTypeInt64 point_of(vtkPolyData* poly, std::size_t corner) {
  return poly->GetPolys()->GetConnectivityArray64()->GetValue(static_cast<vtkIdType>(corner));
}

// `got` draws what a fresh build of `mesh` at `positions` with `normals` draws.
inline void expect_rebuilt(const ViewPolyData& got, const SurfaceMesh& mesh,
                           const std::vector<glm::vec3>& positions, const Normals* normals,
                           const std::string& what) {
  SCOPED_TRACE(what);
  const ViewPolyData fresh(mesh, positions, normals);
  vtkPolyData *g = got.poly(), *w = fresh.poly();
  ASSERT_EQ(g->GetNumberOfPoints(), w->GetNumberOfPoints());
  EXPECT_EQ(static_cast<std::size_t>(w->GetNumberOfPoints()), distinct_ways(mesh, normals));
  ASSERT_EQ(g->GetNumberOfCells(), w->GetNumberOfCells());
  vtkDataArray *gv = g->GetPointData()->GetArray("vertex_id"), *wv = w->GetPointData()->GetArray("vertex_id");
  vtkDataArray *gn = g->GetPointData()->GetNormals(), *wn = w->GetPointData()->GetNormals();
  vtkDataArray *gt = g->GetPointData()->GetArray("uv0"), *wt = w->GetPointData()->GetArray("uv0");
  ASSERT_EQ(gn == nullptr, wn == nullptr);
  ASSERT_EQ(gt == nullptr, wt == nullptr);
  vtkDataArray *gf = g->GetCellData()->GetArray("face_id"), *wf = w->GetCellData()->GetArray("face_id");
  for (std::uint32_t f = 0; f < mesh.face_slots(); ++f) {
    ASSERT_EQ(gf->GetTuple1(f), wf->GetTuple1(f)) << "face " << f;
    if (mesh.is_deleted(FaceId(f))) {
      EXPECT_EQ(point_of(g, 3 * f), point_of(g, 3 * f + 1)) << "deleted face " << f;
      EXPECT_EQ(point_of(g, 3 * f), point_of(g, 3 * f + 2)) << "deleted face " << f;
      continue;
    }
    for (std::uint32_t c = 3 * f; c < 3 * f + 3; ++c) {
      const vtkIdType a = point_of(g, c), b = point_of(w, c);
      ASSERT_TRUE(a >= 0 && a < g->GetNumberOfPoints()) << "corner " << c;
      double pa[3], pb[3];
      g->GetPoint(a, pa);
      w->GetPoint(b, pb);
      for (int i = 0; i < 3; ++i) EXPECT_EQ(pa[i], pb[i]) << "corner " << c;
      EXPECT_EQ(gv->GetTuple1(a), wv->GetTuple1(b)) << "corner " << c;
      for (int i = 0; gn && i < 3; ++i)
        EXPECT_EQ(gn->GetComponent(a, i), wn->GetComponent(b, i)) << "corner " << c;
      for (int i = 0; gt && i < 2; ++i)
        EXPECT_EQ(gt->GetComponent(a, i), wt->GetComponent(b, i)) << "corner " << c;
    }
  }
  // Colours the caller set (one per point: its vertex id) are kept only while still true.
  if (vtkDataArray* colors = g->GetPointData()->GetArray("colors")) {
    for (vtkIdType p = 0; p < g->GetNumberOfPoints(); ++p)
      EXPECT_EQ(colors->GetTuple1(p), gv->GetTuple1(p)) << "colour of point " << p;
  }
}

}  // namespace deepcut
