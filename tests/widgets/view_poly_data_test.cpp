// SPDX-License-Identifier: MIT
// ViewPolyData after each step (MeshEditor edits, described by the PrimitiveChange the studio
// passes: diff_meshes of the mesh before and after) equals a fresh build of the same mesh,
// positions and normals: as many points, every corner of a live face drawn alike (position,
// normal, uv, vertex id), face ids per cell, and the corners of a vertex that draw alike
// sharing one point. Headless: VTK data only, no render window.

#include "deepcut/widgets/view_poly_data.h"

#include <gtest/gtest.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkTypeInt64Array.h>

#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/model_change.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/posed_corner_normal.h"
#include "deepcut/core/posed_model.h"
#include "fixtures.h"
#include "view_checks.h"
#include "view_poly_data_writer.h"

namespace deepcut {
namespace {

// Colours every point with its vertex id, as a viewer colouring by vertex would.
void colour_by_vertex(const ViewPolyData& view) {
  vtkPolyData* poly = view.poly();
  vtkNew<vtkFloatArray> colors;
  colors->SetName("colors");
  colors->SetNumberOfTuples(poly->GetNumberOfPoints());
  for (vtkIdType p = 0; p < poly->GetNumberOfPoints(); ++p)
    colors->SetValue(p, static_cast<float>(poly->GetPointData()->GetArray("vertex_id")->GetTuple1(p)));
  poly->GetPointData()->AddArray(colors);
}

// A mesh drawn by a ViewPolyData that follows each step made on it.
struct Followed {
  SurfaceMesh mesh;
  ViewPolyData view;
  explicit Followed(SurfaceMesh m) : mesh(std::move(m)), view(mesh, mesh.positions()) {
    expect_rebuilt(view, mesh, mesh.positions(), nullptr, "build");
  }
  // Turns the mesh into `after` (the studio's step) and checks the view against a rebuild.
  void become(const SurfaceMesh& after, const std::string& what) {
    PrimitiveChange change;
    ASSERT_TRUE(diff_meshes(mesh, after, change)) << what;
    mesh = after;
    colour_by_vertex(view);
    view.update(mesh, mesh.positions(), nullptr, change);
    expect_rebuilt(view, mesh, mesh.positions(), nullptr, what);
  }
  void edit(const std::function<void(MeshEditor&)>& steps, const std::string& what) {
    SurfaceMesh after = mesh;
    MeshEditor editor(after);
    steps(editor);
    become(after, what);
  }
};

std::vector<FaceId> live_faces(const SurfaceMesh& mesh) {
  std::vector<FaceId> out;
  for (std::uint32_t f = 0; f < mesh.face_slots(); ++f)
    if (!mesh.is_deleted(FaceId(f))) out.push_back(FaceId(f));
  return out;
}

// The room each array gets for n elements is not too roomy for them, nor for them less the few
// elements (a few dozen) a step removes (the next adds them back without a reallocation), and too_roomy
// starts past n + 2 x the growth.
TEST(ViewPolyDataTest, room_size_and_too_roomy_agree) {
  for (std::size_t n : {0u, 1u, 7u, 64u, 100u, 1000u, 12345u, 1u << 20, 3000000u}) {
    SCOPED_TRACE(n);
    EXPECT_GT(view_data::room_size(n), n);
    EXPECT_FALSE(view_data::too_roomy(view_data::room_size(n), n));
    for (std::size_t k : {1u, 2u, 3u, 10u, 32u})
      EXPECT_FALSE(view_data::too_roomy(view_data::room_size(n + k), n));
    EXPECT_FALSE(view_data::too_roomy(n + 2 * (n / 8 + 64), n));
    EXPECT_TRUE(view_data::too_roomy(n + n / 4 + 129, n));
  }
  std::vector<std::uint32_t> v(1000, 7);
  view_data::grow(v, 1001);
  EXPECT_EQ(v.capacity(), view_data::room_size(1001));
  v.resize(100);
  view_data::fit(v);
  EXPECT_EQ(v.capacity(), view_data::room_size(100));
  EXPECT_EQ(v, std::vector<std::uint32_t>(100, 7));
}

TEST(ViewPolyDataTest, every_face_deleted_then_restored) {
  Followed f(test::make_grid(3, 3));
  const SurfaceMesh original = f.mesh;
  f.edit([](MeshEditor& e) { for (FaceId face : live_faces(e.mesh())) e.remove_face(face); }, "all deleted");
  EXPECT_EQ(f.view.poly()->GetNumberOfPoints(), 1);
  f.become(original, "restored");
  f.edit([](MeshEditor& e) { e.remove_face(FaceId(0)); }, "one deleted");
  f.become(original, "restored again");
}

TEST(ViewPolyDataTest, last_points_only_corner_removed) {
  Followed f(test::make_grid(2, 2));
  // A new vertex whose only corner draws the last point, then its face removed.
  FaceId added;
  f.edit([&](MeshEditor& e) {
    const Triangle t = e.mesh().face(FaceId(0));
    const VertexId v = e.add_vertex_in_triangle(t, {0.2f, 0.3f, 0.5f});
    added = e.add_face({t[0], t[1], v});
  }, "vertex added");
  f.edit([&](MeshEditor& e) { e.remove_face(added); }, "its face removed");
  // The last vertex with a single corner in a fresh layout: its point is the last.
  std::vector<int> corners(f.mesh.vertex_count(), 0);
  for (FaceId face : live_faces(f.mesh))
    for (int k = 0; k < 3; ++k) ++corners[f.mesh.face(face)[k].index];
  FaceId lone;
  for (FaceId face : live_faces(f.mesh))
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = f.mesh.face(face)[k].index;
      if (corners[v] == 1 && (!lone.valid() || v > f.mesh.face(lone)[0].index)) lone = face;
    }
  ASSERT_TRUE(lone.valid());
  f.edit([&](MeshEditor& e) { e.remove_face(lone); }, "lone corner removed");
}

TEST(ViewPolyDataTest, pose_with_posed_normals) {
  Followed f(test::make_grid(3, 2));
  std::vector<glm::vec3> posed = f.mesh.positions();
  for (glm::vec3& p : posed) p = {p.y * 2.0f, -p.x, p.z + 1.0f};
  const auto& own = f.mesh.corner_attrs().find<glm::vec3>(attr::kNormal)->data();
  Normals normals(own.size());
  for (std::size_t c = 0; c < own.size(); ++c) normals[c] = {own[c].z, 0.0f, -own[c].x};  // a rotation
  f.view.set_positions(posed, &normals);
  expect_rebuilt(f.view, f.mesh, posed, &normals, "posed");
  // A step drawn in the pose.
  SurfaceMesh after = f.mesh;
  MeshEditor(after).remove_face(FaceId(3));
  PrimitiveChange change;
  ASSERT_TRUE(diff_meshes(f.mesh, after, change));
  f.mesh = after;
  f.view.update(f.mesh, posed, &normals, change);
  expect_rebuilt(f.view, f.mesh, posed, &normals, "posed step");
}

TEST(ViewPolyDataTest, uv_seam) {
  Followed f(test::make_grid(4, 2));  // a seam down x = 0.5
  const SurfaceMesh original = f.mesh;
  std::vector<FaceId> seam;
  for (FaceId face : live_faces(f.mesh))
    for (int k = 0; k < 3; ++k)
      if (f.mesh.position(f.mesh.face(face)[k]).x == 0.5f) {
        seam.push_back(face);
        break;
      }
  ASSERT_FALSE(seam.empty());
  f.edit([&](MeshEditor& e) { for (std::size_t i = 0; i < seam.size(); i += 2) e.remove_face(seam[i]); },
         "half the seam's faces removed");
  f.edit([&](MeshEditor& e) {
    for (std::uint32_t v = 0; v < e.mesh().vertex_count(); ++v) {
      const glm::vec3 p = e.mesh().position(VertexId(v));
      if (p.x == 0.5f) e.move_vertex(VertexId(v), p + 0.1f);
    }
  }, "seam vertices moved");
  f.become(original, "seam restored");
}

// A fan of 72 faces round vertex 0 whose corners there draw in 36 ways (texture coordinates
// (i % 36, 0)), each twice: more ways than a vertex's few remembered points.
SurfaceMesh make_many_ways_fan() {
  constexpr int kFaces = 72, kWays = 36;
  SurfaceMesh mesh;
  const VertexId centre = mesh.add_vertex({0.0f, 0.0f, 0.0f});
  for (int i = 0; i < kFaces; ++i) {
    const float a = 6.2831853f * static_cast<float>(i) / kFaces;
    mesh.add_vertex({std::cos(a), std::sin(a), 0.0f});
  }
  auto& uv = mesh.corner_attrs().add<glm::vec2>(attr::kUv0);
  for (int i = 0; i < kFaces; ++i) {
    const VertexId a(static_cast<std::uint32_t>(1 + i)), b(static_cast<std::uint32_t>(1 + (i + 1) % kFaces));
    const FaceId f = mesh.add_face(centre, a, b);
    uv[SurfaceMesh::corner(f, 0)] = {static_cast<float>(i % kWays), 0.0f};
    uv[SurfaceMesh::corner(f, 1)] = {0.0f, 1.0f};
    uv[SurfaceMesh::corner(f, 2)] = {1.0f, 1.0f};
  }
  return mesh;
}

TEST(ViewPolyDataTest, more_ways_than_remembered_on_one_vertex) {
  Followed f(make_many_ways_fan());
  const SurfaceMesh original = f.mesh;
  // New corners at the centre, in another order than a fresh build lists them.
  f.edit([](MeshEditor& e) {
    for (std::uint32_t i = 0; i < 8; ++i) e.remove_face(FaceId(i));
  }, "first faces removed");
  f.become(original, "first faces restored");
  f.edit([](MeshEditor& e) {
    for (std::uint32_t i = 30; i < 72; i += 3) e.remove_face(FaceId(i));
  }, "every third face removed");
  f.become(original, "restored");
}

// The fan with a face naming its centre three times (its corners draw alike, so a point three
// times in its cell): steps after the first build still find every corner of that face.
TEST(ViewPolyDataTest, face_naming_one_vertex_three_times) {
  SurfaceMesh mesh = make_many_ways_fan();
  const FaceId lone = mesh.add_face(VertexId(0), VertexId(0), VertexId(0));
  auto& uv = *mesh.corner_attrs().find<glm::vec2>(attr::kUv0);
  for (int k = 0; k < 3; ++k) uv[SurfaceMesh::corner(lone, k)] = {5.0f, 5.0f};
  Followed f(std::move(mesh));
  const SurfaceMesh original = f.mesh;
  f.edit([](MeshEditor& e) { e.remove_face(FaceId(1)); }, "a face beside removed");
  f.edit([](MeshEditor& e) { e.move_vertex(VertexId(0), {0.0f, 0.0f, 1.0f}); }, "centre moved");
  f.become(original, "restored");
}

// The bytes of a view's drawn arrays: points, normals, uv0, vertex ids, connectivity.
std::vector<std::vector<unsigned char>> view_arrays(const ViewPolyData& view) {
  auto bytes = [](vtkDataArray* a) {
    const auto* p = static_cast<const unsigned char*>(a->GetVoidPointer(0));
    return std::vector<unsigned char>(p, p + a->GetNumberOfValues() * a->GetDataTypeSize());
  };
  vtkPolyData* poly = view.poly();
  return {bytes(poly->GetPoints()->GetData()), bytes(poly->GetPointData()->GetNormals()),
          bytes(poly->GetPointData()->GetArray("uv0")), bytes(poly->GetPointData()->GetArray("vertex_id")),
          bytes(poly->GetPolys()->GetConnectivityArray())};
}

// The first build's arrays, byte for byte, are the same whatever the thread count (the corners
// are grouped by vertex ranges, one per thread), and so is the view after a step.
TEST(ViewPolyDataTest, first_build_the_same_whatever_the_thread_count) {
  const SurfaceMesh mesh = test::make_grid(40, 30);
  const std::size_t threads = thread_count();
  std::vector<std::vector<std::vector<unsigned char>>> got;
  for (std::size_t n : {1, 2, 3, 7}) {
    set_thread_count(n);
    Followed f(mesh);
    EXPECT_TRUE(f.view.corner_points());
    got.push_back(view_arrays(f.view));
    f.edit([](MeshEditor& e) { e.remove_face(FaceId(5)); }, "a face removed");
  }
  set_thread_count(threads);
  for (std::size_t i = 1; i < got.size(); ++i) EXPECT_EQ(got[i], got[0]) << i;
}

// The arrays of a first build as the plain rule makes them: every vertex's corners ascending,
// each sharing the point of the first corner before it that has the same normal, texture
// coordinates and morph normal deltas bit for bit (else a new point, after the vertex's points
// so far); the vertices' points in vertex order; a deleted face's cell (0, 0, 0).
std::vector<std::vector<unsigned char>> plainly_grouped_arrays(const SurfaceMesh& mesh) {
  const auto& ca = mesh.corner_attrs();
  std::vector<const float*> words;  // per corner: 3 floats each, then 2 for uv
  const glm::vec3* normal =
      ca.find<glm::vec3>(attr::kNormal) ? ca.find<glm::vec3>(attr::kNormal)->data().data() : nullptr;
  const glm::vec2* uv =
      ca.find<glm::vec2>(attr::kUv0) ? ca.find<glm::vec2>(attr::kUv0)->data().data() : nullptr;
  std::vector<const glm::vec3*> deltas;
  for (int t = 0; mesh.vertex_attrs().find<glm::vec3>(attr::morph_position_name(t)); ++t)
    if (const auto* a = ca.find<glm::vec3>(attr::morph_normal_name(t))) deltas.push_back(a->data().data());
  auto alike = [&](std::size_t a, std::size_t b) {
    if (normal && std::memcmp(&normal[a], &normal[b], sizeof(glm::vec3)) != 0) return false;
    if (uv && std::memcmp(&uv[a], &uv[b], sizeof(glm::vec2)) != 0) return false;
    for (const glm::vec3* d : deltas)
      if (std::memcmp(&d[a], &d[b], sizeof(glm::vec3)) != 0) return false;
    return true;
  };
  std::vector<std::vector<std::size_t>> corners(mesh.vertex_count());
  for (std::uint32_t f = 0; f < mesh.face_slots(); ++f)
    if (!mesh.is_deleted(FaceId(f)))
      for (int k = 0; k < 3; ++k)
        corners[mesh.face(FaceId(f))[k].index].push_back(3 * f + static_cast<std::size_t>(k));
  std::vector<float> points, normals, uvs;
  std::vector<vtkIdType> vertex_ids;
  std::vector<vtkTypeInt64> conn(3 * mesh.face_slots(), 0);
  for (std::size_t v = 0; v < corners.size(); ++v) {
    std::vector<std::size_t> firsts;  // each point's first corner
    const std::size_t first_point = vertex_ids.size();
    for (std::size_t c : corners[v]) {
      std::size_t p = 0;
      while (p < firsts.size() && !alike(firsts[p], c)) ++p;
      if (p == firsts.size()) {
        firsts.push_back(c);
        const glm::vec3 x = mesh.position(VertexId(static_cast<std::uint32_t>(v)));
        points.insert(points.end(), {x.x, x.y, x.z});
        if (normal) normals.insert(normals.end(), {normal[c].x, normal[c].y, normal[c].z});
        if (uv) uvs.insert(uvs.end(), {uv[c].x, uv[c].y});
        vertex_ids.push_back(static_cast<vtkIdType>(v));
      }
      conn[c] = static_cast<vtkTypeInt64>(first_point + p);
    }
  }
  if (vertex_ids.empty()) {  // a deleted face's cell names point 0
    points.assign(3, 0.0f);
    if (normal) normals.assign(3, 0.0f);
    if (uv) uvs.assign(2, 0.0f);
    vertex_ids.assign(1, 0);
  }
  auto bytes = [](const auto& values) {
    const auto* p = reinterpret_cast<const unsigned char*>(values.data());
    return std::vector<unsigned char>(p, p + values.size() * sizeof(values[0]));
  };
  return {bytes(points), bytes(normals), bytes(uvs), bytes(vertex_ids), bytes(conn)};
}

// A grid with a uv seam, hard normals (every third face turned), a morph target whose normal
// deltas split corners that draw alike otherwise, corners equal but for the sign of a zero or
// equal NaNs, and deleted faces; then the fan with more ways at its centre than are remembered,
// and the grid with five morph targets.
TEST(ViewPolyDataTest, first_build_groups_corners_as_the_plain_rule) {
  SurfaceMesh grid = test::make_grid(12, 9);
  {
    auto& normal = grid.corner_attrs().get<glm::vec3>(attr::kNormal).data();
    auto& uv = grid.corner_attrs().get<glm::vec2>(attr::kUv0).data();
    grid.vertex_attrs().add<glm::vec3>(attr::morph_position_name(0));
    auto& delta = grid.corner_attrs().add<glm::vec3>(attr::morph_normal_name(0)).data();
    for (std::size_t c = 0; c < normal.size(); ++c) {
      const std::size_t f = c / 3;
      if (f % 3 == 0) normal[c] = glm::normalize(glm::vec3(0.0f, 0.6f, 0.8f));  // hard edges
      if (f % 7 == 2) normal[c].x = -0.0f;                                      // equal but not bitwise
      if (f % 5 == 1) delta[c] = {0.0f, 0.25f, 0.0f};                           // a morph seam
      if ((f / 2) % 11 == 2) uv[c].y = std::nanf("");  // both faces of a cell: equal bits, unequal values
    }
  }
  {
    MeshEditor editor(grid);
    for (std::uint32_t f = 3; f < grid.face_slots(); f += 17) editor.remove_face(FaceId(f));
  }
  ASSERT_LT(grid.face_count(), grid.face_slots());
  SurfaceMesh fan = make_many_ways_fan();
  fan.corner_attrs()
      .add<glm::vec3>(attr::kNormal)
      .data()
      .assign(3 * fan.face_slots(), glm::vec3(0.0f, 0.0f, 1.0f));
  // More morph targets than the grouping's fixed words hold (its plain comparison).
  SurfaceMesh targets = grid;
  for (int t = 1; t < 5; ++t) {
    targets.vertex_attrs().add<glm::vec3>(attr::morph_position_name(t));
    auto& delta = targets.corner_attrs().add<glm::vec3>(attr::morph_normal_name(t)).data();
    for (std::size_t c = 0; c < delta.size(); ++c)
      if ((c / 3) % (5 + static_cast<std::size_t>(t)) == 0)
        delta[c] = {0.1f * static_cast<float>(t), 0.0f, 0.0f};
  }
  const std::size_t threads = thread_count();
  for (const SurfaceMesh* mesh : {&grid, &fan, &targets}) {
    const auto expected = plainly_grouped_arrays(*mesh);
    EXPECT_GT(expected[3].size() / sizeof(vtkIdType), mesh->vertex_count() + 40);  // seams
    for (std::size_t n : {1, 2, 3}) {
      set_thread_count(n);
      const ViewPolyData view(*mesh, mesh->positions());
      ASSERT_TRUE(view.corner_points());
      EXPECT_EQ(view_arrays(view), expected) << n << " threads";
    }
  }
  set_thread_count(threads);
}

// The build that poses a normal per point (an open's first frame) makes the arrays of the build
// given the posed corner normals, byte for byte.
TEST(ViewPolyDataTest, normals_posed_per_point_as_per_corner) {
  SurfaceMesh mesh = test::make_grid(12, 9);
  auto& own = mesh.corner_attrs().get<glm::vec3>(attr::kNormal).data();
  for (std::size_t c = 0; c < own.size(); ++c)  // corners of a vertex drawn in several ways
    own[c] = glm::normalize(glm::vec3(0.1f * static_cast<float>(c % 3), 0.2f, 1.0f));
  PosedMesh pose;
  pose.posed = mesh.positions();
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const float a = 0.1f * static_cast<float>(v);
    pose.linear.push_back(glm::mat3(std::cos(a), std::sin(a), 0.0f, -std::sin(a), std::cos(a), 0.0f, 0.0f,
                                    0.0f, 1.0f + 0.01f * static_cast<float>(v)));
  }
  const std::vector<glm::vec3> normals = pose.corner_normals(mesh);
  ASSERT_EQ(normals.size(), 3 * mesh.face_slots());
  const ViewPolyData per_corner(mesh, pose.posed, &normals);
  const ViewPolyData per_point(mesh, pose.posed, CornerNormalPoser(pose, mesh));
  EXPECT_GT(per_point.poly()->GetNumberOfPoints(), static_cast<vtkIdType>(mesh.vertex_count()));
  EXPECT_EQ(view_arrays(per_point), view_arrays(per_corner));
}

}  // namespace
}  // namespace deepcut
