// SPDX-License-Identifier: MIT
// The drill's wall on its own (core/src/ops/drill/walls/wall.h): rims made by hand, in meshes
// built in code, closed by build_drill_walls without drilling.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/surface_mesh.h"
#include "ops/drill/walls/wall.h"

namespace deepcut {
namespace {

constexpr float kPi = 3.14159265358979f;
constexpr int kSides = 32;
constexpr float kR = 0.5f, kOuter = 2.0f, kHalf = 0.5f;  // hole radius, washer radius, half height

// A thick washer around the z axis (z in [-kHalf, kHalf]) whose hole, a kSides-gon inscribed in
// the circle of radius kR, has no inner side: two boundary loops, at the top and at the bottom.
// With `blind`, the bottom is a full disk instead (one loop, at the top).
SurfaceMesh make_washer(bool blind) {
  SurfaceMesh mesh;
  std::vector<VertexId> ti, to, bi, bo;
  for (int i = 0; i < kSides; ++i) {
    const float a = 2.0f * kPi * float(i) / float(kSides), c = std::cos(a), s = std::sin(a);
    ti.push_back(mesh.add_vertex({kR * c, kR * s, kHalf}));
    to.push_back(mesh.add_vertex({kOuter * c, kOuter * s, kHalf}));
    bi.push_back(mesh.add_vertex({kR * c, kR * s, -kHalf}));
    bo.push_back(mesh.add_vertex({kOuter * c, kOuter * s, -kHalf}));
  }
  const VertexId centre = blind ? mesh.add_vertex({0.0f, 0.0f, -kHalf}) : VertexId();
  for (int i = 0; i < kSides; ++i) {
    const int j = (i + 1) % kSides;
    mesh.add_face(ti[i], to[i], to[j]);  // top, facing +z
    mesh.add_face(ti[i], to[j], ti[j]);
    mesh.add_face(bi[i], bo[j], bo[i]);  // bottom, facing -z
    mesh.add_face(bi[i], bi[j], bo[j]);
    mesh.add_face(bo[i], bo[j], to[j]);  // outer side, facing out
    mesh.add_face(bo[i], to[j], to[i]);
    if (blind) mesh.add_face(centre, bi[j], bi[i]);
  }
  return mesh;
}

// The mesh's boundary loops as rims: chains of half-edges that have no reverse (the surface on
// the left of each step, as the drill's rims).
std::vector<drill::Rim> boundary_rims(const SurfaceMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> half;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (int k = 0; k < 3; ++k) ++half[{t[k].index, t[(k + 1) % 3].index}];
  });
  std::map<std::uint32_t, std::uint32_t> next;
  for (const auto& [e, n] : half)
    if (!half.count({e.second, e.first})) next[e.first] = e.second;
  std::vector<drill::Rim> rims;
  while (!next.empty()) {
    drill::Rim rim;
    std::uint32_t v = next.begin()->first;
    while (next.count(v)) {
      rim.vertices.push_back(VertexId(v));
      const std::uint32_t w = next[v];
      next.erase(v);
      v = w;
    }
    rims.push_back(std::move(rim));
  }
  return rims;
}

struct Walled {
  SurfaceMesh mesh;
  drill::WallResult result;
  std::size_t old_vertices = 0;
};

Walled wall(SurfaceMesh mesh, const Cylinder& cylinder, std::vector<drill::Rim> rims) {
  Walled out;
  out.old_vertices = mesh.vertex_count();
  const std::vector<glm::vec3> posed = mesh.positions();
  std::vector<FaceId> faces;
  mesh.for_each_face([&](FaceId f, const Triangle&) { faces.push_back(f); });
  DrillOptions options;
  options.min_rim_edges = kSides;
  const drill::CylinderFrame cyl = drill::CylinderFrame::make(cylinder, options);
  drill::PosedOverlay overlay(posed, drill::Unposer{});
  MeshEditor editor(mesh);
  out.result = drill::build_drill_walls(editor, cyl, rims, overlay, faces);
  out.mesh = std::move(mesh);
  return out;
}

// Every directed edge once, and its reverse too: closed and consistently oriented.
void expect_closed_and_oriented(const SurfaceMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> half;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (int k = 0; k < 3; ++k) ++half[{t[k].index, t[(k + 1) % 3].index}];
  });
  for (const auto& [e, n] : half) {
    EXPECT_EQ(n, 1) << "edge " << e.first << "-" << e.second << " used twice the same way";
    EXPECT_TRUE(half.count({e.second, e.first})) << "edge " << e.first << "-" << e.second << " on a boundary";
  }
}

std::size_t flagged_faces(const SurfaceMesh& mesh) {
  const auto* flag = mesh.face_attrs().find<std::uint8_t>(attr::kCutSurface);
  std::size_t n = 0;
  mesh.for_each_face([&](FaceId f, const Triangle&) { n += flag && (*flag)[f.index]; });
  return n;
}

double polygon_area(int sides, double radius) {
  return 0.5 * sides * radius * radius * std::sin(2.0 * kPi / sides);
}

TEST(DrillWallTest, two_rims_through_a_washer_get_a_closed_tube_on_the_cylinder) {
  const SurfaceMesh washer = make_washer(false);
  const std::vector<drill::Rim> rims = boundary_rims(washer);
  ASSERT_EQ(rims.size(), 2u);
  const Walled w = wall(washer, Cylinder{{0, 0, -2}, {0, 0, 2}, kR}, rims);
  ASSERT_EQ(w.result.walled.size(), 2u);
  EXPECT_TRUE(w.result.walled[0] && w.result.walled[1]);
  EXPECT_GT(w.result.wall_triangles, 0u);
  EXPECT_EQ(w.result.triangles_removed, 0u);
  EXPECT_EQ(flagged_faces(w.mesh), w.result.wall_triangles);
  expect_closed_and_oriented(w.mesh);
  for (std::size_t v = w.old_vertices; v < w.mesh.vertex_count(); ++v) {
    const glm::vec3 p = w.mesh.positions()[v];
    EXPECT_NEAR(std::hypot(p.x, p.y), kR, 1e-5) << "wall vertex " << v << " off the cylinder";
    EXPECT_GE(p.z, -kHalf - 1e-6f);
    EXPECT_LE(p.z, kHalf + 1e-6f);
  }
  // The wall runs between the hole's polygon and the circle through its corners.
  const double outer = polygon_area(kSides, kOuter), height = 2.0 * kHalf;
  const double volume = w.mesh.volume();
  EXPECT_GE(volume, height * (outer - kPi * kR * kR) - 1e-5);
  EXPECT_LE(volume, height * (outer - polygon_area(kSides, kR)) + 1e-5);
}

TEST(DrillWallTest, a_blind_hole_gets_its_side_and_the_end_disk_inside_the_solid) {
  const SurfaceMesh washer = make_washer(true);
  const std::vector<drill::Rim> rims = boundary_rims(washer);
  ASSERT_EQ(rims.size(), 1u);
  // The cylinder starts at z = 0, inside the solid: the wall is a cup down to its end disk.
  const Walled w = wall(washer, Cylinder{{0, 0, 0}, {0, 0, 2}, kR}, rims);
  ASSERT_EQ(w.result.walled.size(), 1u);
  EXPECT_TRUE(w.result.walled[0]);
  expect_closed_and_oriented(w.mesh);
  bool reaches_bottom = false;
  for (std::size_t v = w.old_vertices; v < w.mesh.vertex_count(); ++v) {
    const glm::vec3 p = w.mesh.positions()[v];
    const double rho = std::hypot(p.x, p.y);
    const bool on_side = std::abs(rho - kR) <= 1e-5 && p.z >= -1e-6f && p.z <= kHalf + 1e-6f;
    const bool on_disk = std::abs(p.z) <= 1e-6f && rho <= kR + 1e-5;
    EXPECT_TRUE(on_side || on_disk) << "wall vertex " << v << " at rho " << rho << " z " << p.z;
    reaches_bottom |= on_disk;
  }
  EXPECT_TRUE(reaches_bottom);
  const double solid = polygon_area(kSides, kOuter) * 2.0 * kHalf;
  const double volume = w.mesh.volume();
  EXPECT_GE(volume, solid - kPi * kR * kR * kHalf - 1e-5);
  EXPECT_LE(volume, solid - polygon_area(kSides, kR) * kHalf + 1e-5);
}

TEST(DrillWallTest, a_shell_with_an_open_rim_gets_no_wall) {
  const SurfaceMesh washer = make_washer(false);
  std::vector<drill::Rim> rims = boundary_rims(washer);
  ASSERT_EQ(rims.size(), 2u);
  rims[1].closed = false;  // it joined an older boundary: the shell was open already
  const Walled w = wall(washer, Cylinder{{0, 0, -2}, {0, 0, 2}, kR}, rims);
  ASSERT_EQ(w.result.walled.size(), 2u);
  EXPECT_FALSE(w.result.walled[0] || w.result.walled[1]);
  EXPECT_EQ(w.result.wall_triangles, 0u);
  EXPECT_EQ(w.mesh.face_count(), washer.face_count());
  EXPECT_EQ(w.mesh.vertex_count(), washer.vertex_count());
}

}  // namespace
}  // namespace deepcut
