// SPDX-License-Identifier: MIT
// The drill on whole meshes and models: round holes, walls, posed drills, random drills on every
// asset, the incremental adjacency. The rim's special cases are in drill_rim_test.cpp.
#include "deepcut/core/ops/drill.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <random>
#include <set>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/ops/tear.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/spatial_index.h"
#include "deepcut/core/validate.h"
#include "drill_checks.h"
#include "fixtures.h"
#include "geometry/predicates.h"
#include "tools.h"

namespace deepcut {
namespace {

using geometry::kPi;
using test::Axis;
using test::census;
using test::check_asset_drill;
using test::check_drill;
using test::Checked;
using test::drilled_volume;
using test::EdgeCensus;
using test::min_angle;

// An axis through a random point of the box; with `finite`, A and B at random distances from
// that point (often inside the model: blind holes, holes starting inside, notches at the ends).
Cylinder random_through_drill(const BoundingBox& box, std::mt19937& rng, bool finite = false) {
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  glm::vec3 dir;
  do dir = {gauss(rng), gauss(rng), gauss(rng)};
  while (glm::length(dir) < 1e-3f);
  dir = glm::normalize(dir);
  const float size = box.diagonal();
  const glm::vec3 p =
      box.min +
      (box.max - box.min) * glm::vec3(0.2f + 0.6f * u01(rng), 0.2f + 0.6f * u01(rng), 0.2f + 0.6f * u01(rng));
  Cylinder c;
  c.a = p - dir * size * (finite ? 0.05f + 0.6f * u01(rng) : 1.0f);
  c.b = p + dir * size * (finite ? 0.05f + 0.6f * u01(rng) : 1.0f);
  c.radius = size * (0.01f + 0.14f * u01(rng));
  return c;
}

}  // namespace

TEST(DrillTest, small_hole_inside_one_big_triangle_is_round) {
  SurfaceMesh mesh = test::make_grid(1, 1);  // two triangles
  Cylinder c{{0.7f, 0.3f, -1.0f}, {0.7f, 0.3f, 1.0f}, 0.05f};
  check_drill(mesh, c, {}, 2, false);
  const DrillResult r = drill_mesh(mesh, PosedMesh::at_positions(mesh), c);
  ASSERT_EQ(r.status, OpStatus::Ok);
  ASSERT_EQ(r.holes.size(), 1u);
  EXPECT_TRUE(r.holes[0].closed);
  EXPECT_EQ(std::abs(r.holes[0].winding), 1);
  EXPECT_EQ(r.holes[0].rim.size(), 32u);
  EXPECT_EQ(r.intersection_points, 0u);
  EXPECT_EQ(r.triangles_removed, 1u);
  // The hole's area is the 32-gon's.
  const double polygon = 0.5 * 32 * std::sin(2 * kPi / 32) * 0.05 * 0.05;
  EXPECT_NEAR(mesh.area(), 1.0 - polygon, 1e-5);
}

TEST(DrillTest, hole_across_edges_and_seam_splits_each_edge_once) {
  const SurfaceMesh grid = test::make_grid(4, 4);
  for (const Cylinder& c :
       {Cylinder{{0.5f, 0.5f, -1}, {0.5f, 0.5f, 1}, 0.3f}, Cylinder{{0.4f, 0.45f, -1}, {0.6f, 0.5f, 1}, 0.2f},
        Cylinder{{0.5f, 0.5f, -1}, {0.5f, 0.5f, 1}, 0.25f}}) {
    check_drill(grid, c, {}, 2, false);
    check_drill(grid, c, {}, 2, true);
  }
  SurfaceMesh mesh = grid;
  const Cylinder slanted{{0.4f, 0.45f, -1}, {0.6f, 0.5f, 1}, 0.2f};
  const DrillResult r = drill_mesh(mesh, PosedMesh::at_positions(mesh), slanted);
  // Vertices on edges: one per crossing (on the cylinder), and the Steiner points graded away
  // from the crossings on the kept parts (well outside it).
  const Axis ax(slanted);
  std::size_t added = 0;
  for (const auto& e : r.log.edits)
    if (const auto* a = std::get_if<VertexAdded>(&e))
      added += !a->from[2].valid() && std::abs(ax.rho(mesh.position(a->v)) - ax.r) <= 0.01 * ax.r;
  EXPECT_EQ(added, r.intersection_points);
  ASSERT_EQ(r.holes.size(), 1u);
  EXPECT_GE(r.holes[0].rim.size(), 32u);
}

TEST(DrillTest, rejects_bad_cylinders_and_misses_leave_the_mesh_untouched) {
  const SurfaceMesh tube = test::make_tube(16, 4);
  SurfaceMesh mesh = tube;
  EXPECT_THROW(drill_mesh(mesh, PosedMesh::at_positions(mesh), Cylinder{{0, 1, -2}, {0, 1, 2}, 0.0f}), Error);
  EXPECT_THROW(drill_mesh(mesh, PosedMesh::at_positions(mesh), Cylinder{{0, 1, -2}, {0, 1, 2}, -0.1f}), Error);
  EXPECT_THROW(drill_mesh(mesh, PosedMesh::at_positions(mesh), Cylinder{{0, 1, 2}, {0, 1, 2}, 0.1f}), Error);
  EXPECT_THROW(drill_mesh(mesh, PosedMesh::at_positions(mesh), Cylinder{{0, NAN, -2}, {0, 1, 2}, 0.1f}), Error);
  EXPECT_THROW(drill_mesh(mesh, PosedMesh::at_positions(mesh), Cylinder{{0, 1, -2}, {0, 1, 2}, NAN}), Error);
  DrillOptions few;
  few.min_rim_edges = 2;
  EXPECT_THROW(drill_mesh(mesh, PosedMesh::at_positions(mesh), Cylinder{{0, 1, -2}, {0, 1, 2}, 0.1f}, few), Error);
  EXPECT_THROW(drill_mesh(mesh, PosedMesh::at_positions(mesh, std::vector<glm::vec3>(3)), Cylinder{{0, 1, -2}, {0, 1, 2}, 0.1f}), Error);
  for (const Cylinder& c : {Cylinder{{5, 1, -2}, {5, 1, 2}, 0.5f}, Cylinder{{0, 1, -5}, {0, 1, -3}, 0.5f},
                            Cylinder{{0, 1, -0.5f}, {0, 1, 0.5f}, 0.2f}}) {  // the last lies inside
    SurfaceMesh m = tube;
    const DrillResult r = drill_mesh(m, PosedMesh::at_positions(m), c);
    EXPECT_EQ(r.status, OpStatus::NoIntersection);
    EXPECT_TRUE(r.log.empty());
    EXPECT_EQ(m.faces(), tube.faces());
    EXPECT_EQ(m.vertex_count(), tube.vertex_count());
  }
}

TEST(DrillTest, through_tube_with_wall_is_closed_and_loses_the_drilled_volume) {
  const SurfaceMesh tube = test::make_tube(24, 6, 1.0f, 2.0f);
  DrillOptions options;
  options.wall = true;
  for (const Cylinder& c :
       {Cylinder{{0, 1, -3}, {0, 1, 3}, 0.3f}, Cylinder{{-3, 1.1f, -2}, {3, 0.9f, 2}, 0.25f},
        Cylinder{{0.2f, -1, 0.1f}, {0.1f, 3, -0.2f}, 0.4f}}) {
    const Checked k = check_drill(tube, c, options, 0, true);
    EXPECT_TRUE(k.all_walled);
    EXPECT_EQ(k.round_holes, 2u);
  }
}

// Issue 10 (random sequences, CesiumMan seed 4): walled drills grew the mesh from 4 672 to
// 457 699 triangles. The wall's rows were graded by the rim spacing alone, so a long thin wall
// cost about 2 x rim edges x length / (0.8 r) triangles. A straight wall in one bone needs rows
// only next to its rims: away from them rings keep 24 points and rows are at most 7 of their
// spacings apart, so each radius of length costs at most 2 x 24 / (7 x 2 pi / 24), about 26
// triangles, whatever the rim count; closed, oriented and within the volume (check_drill).
TEST(DrillTest, a_long_wall_in_one_bone_costs_its_rims_not_its_length) {
  const float r = 0.1f;
  auto wall_triangles = [&](float length, int rim_edges) {
    SurfaceMesh tube = test::make_tube(24, 4, 1.0f, length);
    auto& joints = tube.vertex_attrs().add<glm::u16vec4>(attr::kJoints0);
    auto& weights = tube.vertex_attrs().add<glm::vec4>(attr::kWeights0);
    for (std::size_t v = 0; v < tube.vertex_count(); ++v) {
      joints[v] = {0, 0, 0, 0};
      weights[v] = {1.0f, 0.0f, 0.0f, 0.0f};
    }
    DrillOptions options;
    options.wall = true;
    options.min_rim_edges = rim_edges;
    // Along the tube, through both caps: one wall the tube's length long.
    const Cylinder c{{0.05f, -1.0f, 0.03f}, {0.05f, length + 1.0f, 0.03f}, r};
    const Checked k = check_drill(tube, c, options, 1, false);
    EXPECT_TRUE(k.all_walled);
    EXPECT_EQ(k.round_holes, 2u);
    return k.wall;
  };
  for (const int rim_edges : {24, 48, 96}) {
    SCOPED_TRACE(std::to_string(rim_edges) + " rim edges");
    const std::size_t short_wall = wall_triangles(2.0f, rim_edges), long_wall = wall_triangles(8.0f, rim_edges);
    std::printf("%d rim edges: %zu wall triangles at 20 r, %zu at 80 r\n", rim_edges, short_wall, long_wall);
    EXPECT_LE(long_wall, short_wall + static_cast<std::size_t>(30.0 * 6.0 / r))
        << "60 r more of straight wall costs about 26 triangles per r, whatever the rim count";
  }
}

// Issue 10 (random sequences, CesiumMan default seed step 275 once the rows were fixed): a shell
// with a boundary of its own has no inside, so its rims' orientation alone picked the wall's
// side. On torn parts that was a cup out to an end of the cylinder, or the whole cylinder but
// a patch where a rim did not go around the axis: 56 such walls in one drill, 131 000
// triangles. An open shell now gets tubes between its rims only.
TEST(DrillTest, an_open_shell_gets_tubes_between_its_rims_but_no_cup) {
  DrillOptions options;
  options.wall = true;
  // An open sheet: one rim around the axis, nothing to join it to.
  SurfaceMesh sheet = test::make_grid(8, 8);
  const DrillResult cup = drill_mesh(sheet, PosedMesh::at_positions(sheet), Cylinder{{0.47f, 0.52f, -1}, {0.47f, 0.52f, 1}, 0.1f}, options);
  ASSERT_EQ(cup.status, OpStatus::Ok);
  ASSERT_EQ(cup.holes.size(), 1u);
  EXPECT_FALSE(cup.holes[0].walled);
  EXPECT_EQ(cup.wall_triangles, 0u);
  // A closed tube torn open at one cap (far from the drill): the drill across it still gets
  // its tube from the entry rim to the exit rim, and the cap's gap is the only boundary.
  SurfaceMesh torn = test::make_tube(24, 6, 1.0f, 2.0f);
  {
    MeshEditor editor(torn);
    editor.remove_face(FaceId(2 * 24 * 6 + 1));  // a face of the cap at y = 2
  }
  const Adjacency before = Adjacency::build(torn);
  ASSERT_EQ(before.boundary_edges().size(), 3u);
  SurfaceMesh mesh = torn;
  const DrillResult tube = drill_mesh(mesh, PosedMesh::at_positions(mesh), Cylinder{{0, 1, -3}, {0, 1, 3}, 0.3f}, options);
  ASSERT_EQ(tube.holes.size(), 2u);
  for (const DrillHole& h : tube.holes) EXPECT_TRUE(h.walled);
  EXPECT_GT(tube.wall_triangles, 0u);
  EXPECT_EQ(Adjacency::build(mesh).boundary_edges().size(), 3u);
  test::expect_valid(mesh);
}

// Found by the random sequences (CesiumMan seed 1 step 247, Fox seed 5 step 132): where the
// posed skin passes through itself (a fold at a joint), one hole's rim crosses itself on the
// cylinder; no wall lying on the cylinder can close it, and the hole was left open. A tube bent
// by 170 degrees at its joint (linear blend skinning folds the inner side of the elbow through
// itself), taken as it is posed: the wall folds with the surface and the drill stays closed and
// consistently oriented.
TEST(DrillTest, a_rim_crossing_itself_where_the_surface_does_is_walled) {
  Model model = test::make_skinned_tube_model();
  Pose pose = rest_pose(model);
  pose.rotation[3] = glm::angleAxis(glm::radians(170.0f), glm::vec3(0, 0, 1));
  SurfaceMesh bent = model.meshes[0].primitives[0].mesh;
  bent.positions() = posed_positions(model, 0, bent, world_matrices(model, pose));
  const Cylinder c{{2.418143f, 2.325492f, 1.140820f}, {-3.211093f, 0.937094f, -0.403217f}, 0.252299f};
  for (const int rim_edges : {6, 12, 32}) {
    SCOPED_TRACE(std::to_string(rim_edges) + " rim edges");
    SurfaceMesh mesh = bent;
    DrillOptions options;
    options.wall = true;
    options.min_rim_edges = rim_edges;
    const DrillResult r = drill_mesh(mesh, PosedMesh::at_positions(mesh), c, options);
    ASSERT_EQ(r.status, OpStatus::Ok);
    ASSERT_FALSE(r.holes.empty());
    for (const DrillHole& h : r.holes) EXPECT_TRUE(h.walled);
    const EdgeCensus k = census(mesh);
    EXPECT_EQ(k.boundary, 0u) << "closed";
    EXPECT_EQ(k.inconsistent, 0u) << "consistently oriented";
    test::expect_valid(mesh, 2);
    std::set<std::array<std::uint32_t, 3>> faces;
    mesh.for_each_face([&](FaceId, const Triangle& t) {
      std::array<std::uint32_t, 3> key = {t[0].index, t[1].index, t[2].index};
      std::sort(key.begin(), key.end());
      EXPECT_TRUE(faces.insert(key).second) << "duplicate face";
      EXPECT_GT(glm::length(glm::cross(mesh.position(t[1]) - mesh.position(t[0]), mesh.position(t[2]) - mesh.position(t[0]))), 0.0f);
    });
  }
}

TEST(DrillTest, blind_hole_and_start_inside_get_a_disk) {
  const SurfaceMesh tube = test::make_tube(24, 6, 1.0f, 2.0f);
  DrillOptions options;
  options.wall = true;
  // B inside: only the entry wall is drilled, closed by a disk at B.
  const Cylinder blind{{0, 1, -3}, {0, 1, 0.2f}, 0.3f};
  const Checked k = check_drill(tube, blind, options, 0, false);
  EXPECT_TRUE(k.all_walled);
  EXPECT_EQ(k.round_holes, 1u);
  SurfaceMesh mesh = tube;
  const DrillResult r = drill_mesh(mesh, PosedMesh::at_positions(mesh), blind, options);
  ASSERT_EQ(r.holes.size(), 1u);
  for (VertexId v : r.holes[0].rim)
    EXPECT_LT(mesh.position(v).z, -0.9f) << "only the wall before B is drilled";
  // A inside: the exit wall only, with a disk at A.
  const Cylinder inside{{0.1f, 1, 0.3f}, {0.1f, 1, 3}, 0.3f};
  EXPECT_TRUE(check_drill(tube, inside, options, 0, false).all_walled);
  // Without a wall the blind hole is simply open.
  EXPECT_EQ(check_drill(tube, blind, {}, 0, false).round_holes, 1u);
}

TEST(DrillTest, coarse_fox_gets_a_round_hole_with_uvs_inside_the_islands_it_crosses) {
  const Model fox = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/models/Fox/Fox.glb");
  const SurfaceMesh& input = fox.meshes[0].primitives[0].mesh;
  ASSERT_EQ(input.face_count(), 576u);
  const std::size_t joints = fox.skins[0].joints.size();
  for (const Cylinder& c :
       {Cylinder{{-40, 45, 0}, {40, 45, 0}, 4.0f}, Cylinder{{-40, 40, -30}, {40, 42, -25}, 6.0f},
        Cylinder{{0, 120, 10}, {0, -20, 10}, 3.0f}}) {
    const Checked k = check_drill(input, c, {}, joints, false);
    EXPECT_GE(k.round_holes, 1u);
    SurfaceMesh mesh = input;
    const DrillResult r = drill_mesh(mesh, PosedMesh::at_positions(mesh), c);
    ASSERT_EQ(r.status, OpStatus::Ok);
    for (const DrillHole& h : r.holes) {
      if (h.closed && std::abs(h.winding) == 1) {
        EXPECT_GE(h.rim.size(), 32u);
      }
    }
    // Every new corner's UV is a convex combination of its parent triangle's UVs: inside the
    // texture island the parent belongs to, never stretched across a seam.
    const auto& uv = mesh.corner_attrs().get<glm::vec2>(attr::kUv0);
    std::size_t checked = 0;
    for (const Edit& e : r.log.edits) {
      const auto* a = std::get_if<FaceAdded>(&e);
      if (!a || !a->parent.valid()) continue;
      const glm::vec2 p0 = uv[SurfaceMesh::corner(a->parent, 0)], p1 = uv[SurfaceMesh::corner(a->parent, 1)],
                      p2 = uv[SurfaceMesh::corner(a->parent, 2)];
      const float area = (p1.x - p0.x) * (p2.y - p0.y) - (p2.x - p0.x) * (p1.y - p0.y);
      if (std::abs(area) < 1e-12f) continue;
      for (int k2 = 0; k2 < 3; ++k2) {
        const glm::vec2 q = uv[SurfaceMesh::corner(a->f, k2)];
        const float b1 = ((q.x - p0.x) * (p2.y - p0.y) - (p2.x - p0.x) * (q.y - p0.y)) / area;
        const float b2 = ((p1.x - p0.x) * (q.y - p0.y) - (q.x - p0.x) * (p1.y - p0.y)) / area;
        EXPECT_GE(b1, -1e-3f);
        EXPECT_GE(b2, -1e-3f);
        EXPECT_LE(b1 + b2, 1.0f + 1e-3f);
        ++checked;
      }
    }
    EXPECT_GT(checked, 0u);
  }
}

// Boundary edges grouped into connected chains (union-find over their vertices).
std::size_t boundary_components(const Adjacency& adj) {
  std::map<std::uint32_t, std::uint32_t> parent;
  std::function<std::uint32_t(std::uint32_t)> root = [&](std::uint32_t x) {
    if (!parent.count(x)) parent[x] = x;
    return parent[x] == x ? x : parent[x] = root(parent[x]);
  };
  for (const Edge& e : adj.boundary_edges()) parent[root(e.a.index)] = root(e.b.index);
  std::set<std::uint32_t> roots;
  for (const auto& [v, p] : parent) roots.insert(root(v));
  return roots.size();
}

TEST(DrillTest, overlapping_holes_and_a_cut_rim_merge_into_one_boundary) {
  const SurfaceMesh grid = test::make_grid(6, 6);
  const Cylinder first{{0.4f, 0.5f, -1}, {0.4f, 0.5f, 1}, 0.2f},
      second{{0.62f, 0.52f, -1}, {0.62f, 0.52f, 1}, 0.18f};
  SurfaceMesh mesh = grid;
  Adjacency adj = Adjacency::build(mesh);
  for (const Cylinder& c : {first, second}) {
    const DrillResult r = drill_mesh(mesh, PosedMesh::at_positions(mesh), c);
    ASSERT_EQ(r.status, OpStatus::Ok);
    adj.apply(r.log);
  }
  test::expect_adjacency_matches_rebuild(adj, mesh);
  test::expect_valid(mesh, 2);
  EXPECT_EQ(boundary_components(adj), 2u) << "the outer border and one merged hole";
  for (const Cylinder& c : {first, second}) {
    const Axis ax(c);
    mesh.for_each_face([&](FaceId, const Triangle& t) {
      const glm::vec3 m = (mesh.position(t[0]) + mesh.position(t[1]) + mesh.position(t[2])) / 3.0f;
      EXPECT_GE(ax.rho(m), 0.99 * ax.r);
    });
  }
  // Every hole vertex lies on one of the two circles.
  for (const Edge& e : adj.boundary_edges())
    for (VertexId v : {e.a, e.b}) {
      const glm::vec3 p = mesh.position(v);
      const bool border = p.x <= 1e-6f || p.y <= 1e-6f || p.x >= 1 - 1e-6f || p.y >= 1 - 1e-6f;
      const double d1 = std::abs(Axis(first).rho(p) - first.radius) / first.radius;
      const double d2 = std::abs(Axis(second).rho(p) - second.radius) / second.radius;
      EXPECT_TRUE(border || d1 <= 0.01 || d2 <= 0.01) << p.x << "," << p.y;
    }
  // Across a cut: the two pieces each get half a hole whose rims end on the cut line.
  SurfaceMesh cut = grid;
  Adjacency cadj = Adjacency::build(cut);
  cadj.apply(cut_mesh(cut, cut.positions(), Plane{{0.5f, 0, 0}, {1, 0.1f, 0}}).log);
  const DrillResult r = drill_mesh(cut, PosedMesh::at_positions(cut), first);
  ASSERT_EQ(r.status, OpStatus::Ok);
  cadj.apply(r.log);
  test::expect_adjacency_matches_rebuild(cadj, cut);
  test::expect_valid(cut, 2);
  EXPECT_EQ(boundary_components(cadj), 2u) << "each piece keeps one border, now with a bite out of it";
  std::size_t open = 0;
  for (const DrillHole& h : r.holes) open += !h.closed;
  EXPECT_EQ(open, 2u) << "one rim chain per piece, ending on the cut";
  // Across a tear: the slit and the hole become one opening.
  SurfaceMesh torn = test::make_grid(8, 8);
  Adjacency tadj = Adjacency::build(torn);
  TearOptions topt;
  topt.width = 0.02f;
  PosedMesh torn_posed = PosedMesh::at_positions(torn);
  const TearResult tr = tear_mesh(torn, torn_posed, Blade{{0.3f, 0.5f, 1}, {0.3f, 0.5f, -1}},
                                  Blade{{0.7f, 0.5f, 1}, {0.7f, 0.5f, -1}}, topt);
  ASSERT_EQ(tr.status, OpStatus::Ok);
  tadj.apply(tr.log);
  ASSERT_EQ(boundary_components(tadj), 2u) << "the border and the slit";
  const Cylinder across{{0.5f, 0.5f, -1}, {0.5f, 0.5f, 1}, 0.1f};
  const DrillResult tdr = drill_mesh(torn, PosedMesh::at_positions(torn), across);
  ASSERT_EQ(tdr.status, OpStatus::Ok);
  tadj.apply(tdr.log);
  test::expect_adjacency_matches_rebuild(tadj, torn);
  test::expect_valid(torn, 2);
  EXPECT_EQ(boundary_components(tadj), 2u) << "the border and one opening: slit and hole merged";
  const Axis tax(across);
  torn.for_each_face([&](FaceId, const Triangle& t) {
    const glm::vec3 m = (torn.position(t[0]) + torn.position(t[1]) + torn.position(t[2])) / 3.0f;
    EXPECT_GE(tax.rho(m), 0.99 * tax.r);
  });
}

// A walled drill that overlaps an earlier walled hole cuts through that hole's wall as through
// any surface: rims and walls merge, and the model stays closed (check_drill asserts closedness,
// orientation and the volume against the mesh with the earlier holes).
TEST(DrillTest, walled_holes_that_overlap_merge_and_stay_closed) {
  const Model cactus = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  SurfaceMesh mesh = cactus.meshes[0].primitives[0].mesh;
  const Adjacency adj = Adjacency::build(mesh);
  ASSERT_TRUE(adj.boundary_edges().empty() && adj.nonmanifold_edges().empty());
  DrillOptions options;
  options.wall = true;
  const Cylinder drills[] = {{{-3, 5, 0}, {3, 5, 0}, 0.4f},                       // through the trunk
                             {{-3, 5.3f, 0}, {3, 5.3f, 0}, 0.4f},                 // overlapping it
                             {{0, 5.15f, -3}, {0, 5.15f, 3}, 0.3f},               // across both
                             {{-0.2f, 5.2f, -3}, {-0.2f, 5.2f, 0.1f}, 0.25f}};  // blind, ending in them
  for (const Cylinder& c : drills) {
    const Checked k = check_drill(mesh, c, options, cactus.skins.empty() ? 0 : cactus.skins[0].joints.size(), false);
    if (::testing::Test::HasFatalFailure()) return;
    ASSERT_TRUE(k.intersected);
    EXPECT_TRUE(k.all_walled);
    drill_mesh(mesh, PosedMesh::at_positions(mesh), c, options);
  }
  const EdgeCensus c = census(mesh);
  EXPECT_EQ(c.boundary, 0u);
  EXPECT_EQ(c.inconsistent, 0u);
}

TEST(DrillTest, posed_drill_puts_rims_and_walls_on_the_cylinder_in_that_pose) {
  Model model = test::make_skinned_tube_model();  // tube along +y, bends from y = 2 up
  const float t = 1.0f;                           // the bend's extreme
  const auto world = world_matrices(model, sample_pose(model, 0, t));
  const auto posed_before = posed_positions(model, 0, model.meshes[0].primitives[0].mesh, world);
  // An axis across the bent upper part, through the centre of the posed ring at bind y = 3.5.
  const auto& bind_positions = model.meshes[0].primitives[0].mesh.positions();
  glm::vec3 centre(0.0f);
  int n = 0;
  for (std::size_t v = 0; v < bind_positions.size(); ++v)
    if (std::abs(bind_positions[v].y - 3.5f) < 1e-4f &&
        glm::length(glm::vec2(bind_positions[v].x, bind_positions[v].z)) > 0.1f) {
      centre += posed_before[v];
      ++n;
    }
  ASSERT_GT(n, 0);
  centre /= float(n);
  const Cylinder c{centre + glm::vec3(0, 0, -3), centre + glm::vec3(0, 0, 3), 0.2f};
  DrillOptions options;
  options.wall = true;
  const ModelDrillResult r = drill_model(model, c, options, 0, t);
  ASSERT_EQ(r.status, OpStatus::Ok);
  EXPECT_EQ(r.rim_vertices.size(), 2u);
  ASSERT_EQ(model.meshes[0].primitives.size(), 2u) << "body and wall";
  const Axis ax(c);
  for (const auto& prim : model.meshes[0].primitives) {
    test::expect_valid(prim.mesh, 2);
    const auto posed = posed_positions(model, 0, prim.mesh, world);
    const Adjacency adj = Adjacency::build(prim.mesh);
    std::size_t checked = 0;
    for (const Edge& e : adj.boundary_edges())
      for (VertexId v : {e.a, e.b}) {
        EXPECT_NEAR(ax.rho(posed[v.index]), ax.r, 0.01 * ax.r);
        ++checked;
      }
    EXPECT_GT(checked, 60u);
  }
  // The wall's own vertices sit on the cylinder in the pose too (inverse skinning).
  const auto wall_posed = posed_positions(model, 0, model.meshes[0].primitives[1].mesh, world);
  for (const auto& p : wall_posed) EXPECT_NEAR(ax.rho(p), ax.r, 0.01 * ax.r);
  // The same axis in the bind pose would miss the bent part: the pose matters.
  SurfaceMesh bind = test::make_skinned_tube_model().meshes[0].primitives[0].mesh;
  EXPECT_EQ(drill_mesh(bind, PosedMesh::at_positions(bind), c).status, OpStatus::NoIntersection);
}

TEST(DrillTest, a_cylinder_that_swallows_an_instance_leaves_no_empty_mesh) {
  Model model = test::make_skinned_tube_model();  // radius 0.5, y from 0 to 4
  const ModelDrillResult r = drill_model(model, Cylinder{{0, -1, 0}, {0, 5, 0}, 2.0f});
  ASSERT_EQ(r.status, OpStatus::Ok);
  EXPECT_EQ(model.nodes[0].mesh, -1) << "the node draws nothing rather than an empty mesh";
  const std::string dir = test::temp_dir("drillswallow");
  write_gltf(model, dir + "/empty.glb");
  EXPECT_EQ(read_gltf(dir + "/empty.glb").skins.size(), 1u);
  std::filesystem::remove_all(dir);
}

TEST(DrillTest, random_drills_on_every_asset_keep_all_invariants) {
  // DEEPCUT_DRILL_SEED replays another seed (the invariants must hold for any); CI keeps this one.
  const char* seed_env = std::getenv("DEEPCUT_DRILL_SEED");
  const unsigned seed = seed_env ? static_cast<unsigned>(std::strtoul(seed_env, nullptr, 10)) : 20261122u;
  std::printf("drill random seed %u\n", seed);
  // Replaying one failure: DEEPCUT_DRILL_MODEL (part of the asset's path) and DEEPCUT_DRILL_STEP
  // (the drill's number) check only that drill; the random draws stay the same.
  const char* only_model = std::getenv("DEEPCUT_DRILL_MODEL");
  const char* only_step = std::getenv("DEEPCUT_DRILL_STEP");
  for (const auto& path : test::asset_models()) {
    if (only_model && path.find(only_model) == std::string::npos) continue;
    SCOPED_TRACE(path + " (seed " + std::to_string(seed) + ")");
    const Model model = read_gltf(path);
    const std::size_t joints = model.skins.empty() ? 0 : model.skins[0].joints.size();
    std::mt19937 rng(seed);
    std::size_t hits = 0, wall_hits = 0, walled = 0, round = 0, d_shaped = 0;
    Checked quality;
    bool closed = true;
    for (const auto& mesh : model.meshes)
      for (const auto& prim : mesh.primitives) {
        const BoundingBox box = prim.mesh.bounds();
        const Adjacency adj = Adjacency::build(prim.mesh);
        closed &= adj.boundary_edges().empty() && adj.nonmanifold_edges().empty();
        for (int i = 0; i < 100; ++i) {
          const Cylinder c = random_through_drill(box, rng, i % 4 == 3);
          DrillOptions options;
          options.wall = i % 2 == 1;
          options.min_rim_edges = i % 5 == 2 ? 48 : 32;
          if (only_step && std::atoi(only_step) != i) continue;
          SCOPED_TRACE("drill " + std::to_string(i));
          const Checked k = check_drill(prim.mesh, c, options, joints, (i / 2) % 2 == 0);
          if (::testing::Test::HasFatalFailure()) return;
          hits += k.intersected;
          quality.surface += k.surface, quality.surface_thin += k.surface_thin, quality.wall += k.wall;
          quality.wall_thin += k.wall_thin, quality.degenerate += k.degenerate;
          wall_hits += options.wall && k.intersected;
          walled += options.wall && k.all_walled && k.intersected;
          round += k.round_holes;
          d_shaped += k.d_holes;
        }
      }
    // Radii up to 15% of the model size often sever thin parts (rims that do not go around the
    // axis); the rest are round holes. On closed input every wall drill closes (check_drill
    // asserts closedness, orientation and the volume), also where closed components of the
    // input intersect each other, as the cactus' arms and trunk do.
    if (only_step) continue;
    EXPECT_GT(hits, 50u) << "most random drills through the model hit it";
    EXPECT_GT(round, hits / 20) << "through drills make round holes";
    if (closed) {
      EXPECT_EQ(walled, wall_hits) << "walls close every drill of closed input";
    }
    // Triangle quality: no degenerate triangle. Needles (under 5 degrees) among the new
    // surface triangles of well-shaped parents: 1.4-6.6% on these assets with the graded points
    // on crossed edges (seeds 1-8), up to 10.6% on RiggedSimple's few hundred; held here so they
    // cannot grow (30 more for the small samples); on the walls (Lawson flips on the cylinder)
    // under 5%.
    EXPECT_EQ(quality.degenerate, 0u);
    EXPECT_LE(quality.surface_thin, quality.surface * 8 / 100 + 30) << "surface needles";
    EXPECT_LE(quality.wall_thin, quality.wall / 20) << "wall needles";
    std::printf("%s: %zu hits, %zu fully walled, %zu round holes, %zu D-shaped; under 5 degrees: %zu of %zu new surface "
                "triangles, %zu of %zu wall triangles\n",
                path.c_str(), hits, walled, round, d_shaped, quality.surface_thin, quality.surface, quality.wall_thin,
                quality.wall);
  }
}

TEST(DrillTest, incremental_adjacency_follows_a_random_sequence) {
  const unsigned seed = 77;
  std::printf("drill sequence seed %u\n", seed);
  std::size_t moved = 0;
  for (const auto& path : test::asset_models()) {
    SCOPED_TRACE(path);
    const Model model = read_gltf(path);
    SurfaceMesh mesh = model.meshes[0].primitives[0].mesh;
    const BoundingBox box = mesh.bounds();
    std::vector<glm::vec3> posed = mesh.positions();
    TriangleGrid grid = TriangleGrid::build(mesh, posed);
    Adjacency adj = Adjacency::build(mesh);
    std::mt19937 rng(seed);
    for (int i = 0; i < 12; ++i) {
      Cylinder c = random_through_drill(box, rng);
      c.radius *= 0.5f;
      DrillOptions options;
      options.wall = i % 3 == 0;
      const DrillResult r = drill_mesh(mesh, PosedMesh::at_positions(mesh, posed), c, options);
      // Vertices snapped onto the cylinder move (posed == bind here), then new ones join.
      for (const auto& m : r.moved) {
        EXPECT_LE(glm::length(m.posed - mesh.position(m.v)), 1e-5f * (1.0f + glm::length(m.posed)));
        posed[m.v.index] = m.posed;
      }
      moved += r.moved.size();
      posed.insert(posed.end(), r.added_posed.begin(), r.added_posed.end());
      ASSERT_EQ(posed.size(), mesh.vertex_count());
      grid.apply(r.log, posed);
      adj.apply(r.log);
      test::expect_adjacency_matches_rebuild(adj, mesh);
      test::expect_valid(mesh, model.skins.empty() ? 0 : model.skins[0].joints.size());
      EXPECT_EQ(grid.face_count(), mesh.face_count());
      // The grid finds every face around a moved vertex at its new place.
      std::vector<bool> is_moved(mesh.vertex_count(), false);
      for (const auto& m : r.moved) is_moved[m.v.index] = true;
      mesh.for_each_face([&](FaceId f, const Triangle& t) {
        if (!is_moved[t[0].index] && !is_moved[t[1].index] && !is_moved[t[2].index]) return;
        BoundingBox b;
        for (VertexId v : t) b.add(posed[v.index]);
        const auto found = grid.query_box(b);
        EXPECT_TRUE(std::binary_search(found.begin(), found.end(), f)) << "face around a moved vertex";
      });
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
  EXPECT_GT(moved, 0u) << "some drills snap a vertex onto the cylinder (so the moves are followed)";
}

}  // namespace deepcut
