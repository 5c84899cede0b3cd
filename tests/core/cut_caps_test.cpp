// SPDX-License-Identifier: MIT
// Capped cuts at the edge of what a cap can be: sections that give no cap faces.
#include <gtest/gtest.h>

#include <algorithm>

#include "deepcut/core/ops/cut.h"
#include "deepcut/core/surface_mesh.h"
#include "fixtures.h"

namespace deepcut {
namespace {

// A closed surface whose section is a loop of zero area (three points on a line: two flat
// pyramids on a collinear base) gets no cap faces: the cap's corner attributes are set for none,
// without reading a face past the last (that used to index the face array at its size; a build
// with _GLIBCXX_ASSERTIONS stopped there).
TEST(CutTest, a_cap_that_makes_no_faces_sets_no_attributes) {
  SurfaceMesh mesh;
  const VertexId a = mesh.add_vertex({0, 0, 0}), b = mesh.add_vertex({1, 0, 0}),
                 c = mesh.add_vertex({2, 0, 0});
  const VertexId top = mesh.add_vertex({1, 1, 1}), bottom = mesh.add_vertex({1, 1, -1});
  for (const Triangle& t : {Triangle{top, a, b}, Triangle{top, b, c}, Triangle{top, c, a},
                            Triangle{bottom, b, a}, Triangle{bottom, c, b}, Triangle{bottom, a, c}})
    mesh.add_face(t[0], t[1], t[2]);
  auto& normal = mesh.corner_attrs().add<glm::vec3>(attr::kNormal);
  std::fill(normal.data().begin(), normal.data().end(), glm::vec3(0, 1, 0));
  const std::size_t faces = mesh.face_count();
  CutOptions options;
  options.cap = true;
  const CutResult r = cut_mesh(mesh, mesh.positions(), Plane{{0, 0, 0}, {0, 0, 1}}, options);
  EXPECT_EQ(r.status, OpStatus::Ok);
  EXPECT_EQ(mesh.face_count(), faces);
  EXPECT_EQ(mesh.corner_attrs().get<glm::vec3>(attr::kNormal).data().size(), 3 * mesh.face_slots());
  test::expect_valid(mesh);
}

}  // namespace
}  // namespace deepcut
