// SPDX-License-Identifier: MIT
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
#include "tools.h"

namespace deepcut {
namespace {

constexpr double kPi = 3.14159265358979323846;

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

/// Without and with a wall (and, if `also_indexed`, through the spatial index as well): the drill
/// hits, keeps every check_drill invariant, and with a wall every hole is walled.
void expect_asset_drill_hits_and_walls(const Model& model, const Cylinder& cyl, bool also_indexed) {
  for (const bool wall : {false, true})
    for (const bool indexed : {false, true}) {
      if (indexed && !also_indexed) continue;
      SCOPED_TRACE(std::string(wall ? "wall" : "no wall") + (indexed ? ", indexed" : ""));
      const Checked out = check_asset_drill(model, cyl, wall, indexed);
      if (::testing::Test::HasFatalFailure()) return;
      EXPECT_TRUE(out.intersected);
      if (wall) {
        EXPECT_TRUE(out.all_walled);
      }
    }
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

// Found by the random sequences (pinched vertices after drills, e.g. Fox seed 20261986 step 211):
// a saddle vertex lying on the cylinder's side, its surface rising into the cylinder towards +x
// and -x and falling away towards +y and -y. The kept surface is two wedges (around +y and -y)
// that meet only at that vertex; each gets its own vertex, with and without a wall, and with the
// spatial index.
TEST(DrillTest, rim_through_a_saddle_vertex_leaves_no_pinched_vertex) {
  for (const bool wall : {false, true})
    for (const bool indexed : {false, true}) {
      SCOPED_TRACE(std::string(wall ? "wall" : "no wall") + (indexed ? ", indexed" : ""));
      SurfaceMesh mesh;
      const VertexId v = mesh.add_vertex({0, 0, 0});
      const VertexId ring[4] = {mesh.add_vertex({1, 0, 1}), mesh.add_vertex({0, 1, -1}), mesh.add_vertex({-1, 0, 1}),
                                mesh.add_vertex({0, -1, -1})};
      for (int k = 0; k < 4; ++k) mesh.add_face(v, ring[k], ring[(k + 1) % 4]);
      const std::vector<glm::vec3> posed = mesh.positions();
      Adjacency adj = Adjacency::build(mesh);
      DrillOptions options;
      options.wall = wall;
      // Axis along x at height 0.6, radius 0.6: the cylinder's side touches z = 0 along the x axis.
      const DrillResult r =
          drill_mesh(mesh, PosedMesh::at_positions(mesh, posed), Cylinder{{-2, 0, 0.6f}, {2, 0, 0.6f}, 0.6f}, options);
      ASSERT_EQ(r.status, OpStatus::Ok);
      adj.apply(r.log);
      test::expect_adjacency_matches_rebuild(adj, mesh);
      test::expect_valid(mesh);
      EXPECT_TRUE(test::pinched_vertices(mesh).empty());
      std::size_t at_origin = 0;  // used vertices at the saddle point
      for (std::uint32_t i = 0; i < mesh.vertex_count(); ++i)
        at_origin += glm::length(mesh.position(VertexId(i))) < 1e-6f && !adj.vertex_faces(VertexId(i)).empty();
      EXPECT_EQ(at_origin, 2u);
      EXPECT_EQ(r.added_posed.size(), mesh.vertex_count() - r.first_new_vertex);
    }
}

// Found by random drills with other seeds (DEEPCUT_DRILL_SEED): the corner where a D-shaped
// rim's straight part (on the end plane at B) meets its arc. It was skipped when a crossing lay
// within the rim spacing of it (Fox, seed 1 drill 83; cactus, seed 3 drill 35) or when it lay
// just outside the triangle the rim bends in (cactus, seed 2 drill 15): the chord between the
// two parts then left kept surface up to 2.5% of r inside the cylinder.
TEST(DrillTest, rim_corner_on_an_end_plane_is_kept) {
  const Model cactus = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  const Model fox = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/models/Fox/Fox.glb");
  struct Case {
    const Model* model;
    Cylinder c;
  };
  const Case cases[] = {
      {&fox, {{5.43106747f, 43.0290604f, 0.525301933f}, {9.20565319f, 15.536129f, -40.5920792f}, 14.184804f}},
      {&cactus, {{1.30557191f, 10.2793427f, -1.0248698f}, {-1.61410236f, 4.22243118f, 1.19152451f}, 0.477234244f}},
      {&cactus, {{1.89666462f, 5.35040665f, -1.75495446f}, {-0.600944042f, 2.68694258f, 0.668461919f}, 0.682955205f}}};
  for (const Case& k : cases) {
    expect_asset_drill_hits_and_walls(*k.model, k.c, false);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

// Found by random drills (cactus, seed 2 drill 1, with a wall): where two rims meet at one vertex
// on the cylinder, each incoming rim edge goes on with the outgoing one of its own fan. Paired the
// other way, the rims crossed there: the shell could not be walled and, after the pinch split,
// the hole's rim ran along an edge that no longer existed.
TEST(DrillTest, rims_meeting_at_a_vertex_follow_their_own_fans) {
  const Model cactus = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  const Cylinder c{{7.87602472f, 6.90400934f, -5.91235971f}, {-9.16912842f, -1.46460295f, 6.17348909f}, 0.876988471f};
  expect_asset_drill_hits_and_walls(cactus, c, true);
}

// Found by random drills with other seeds (walled drills of closed input that stayed open):
// - cactus, seed 4 drill 11: two rims of one shell touching at a vertex on the cylinder; the
//   hole loop was given to no outer loop, judged at the shared vertex (winding number there is
//   0 or 1 by rounding).
// - RiggedSimple, seed 4 drill 15: a layer that only clips the cylinder's end circle cuts a thin
//   lens; without a point on its arc the rim was the straight part and its chord, a hole of zero
//   area no wall can close.
TEST(DrillTest, walls_close_rims_that_touch_and_thin_lenses_at_an_end) {
  const Model cactus = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  const Model simple = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/models/RiggedSimple/RiggedSimple.gltf");
  struct Case {
    const Model* model;
    Cylinder c;
  };
  const Case cases[] = {
      {&cactus, {{-1.70535243f, 9.63420868f, 4.90398598f}, {1.43953931f, 4.25307465f, -5.2903614f}, 0.674046218f}},
      {&simple, {{2.87141538f, -0.539521337f, 3.19743991f}, {-1.04472518f, 0.391219884f, -4.29873753f}, 0.587547898f}}};
  for (const Case& k : cases) {
    const Checked out = check_asset_drill(*k.model, k.c, true, false);
    if (::testing::Test::HasFatalFailure()) return;
    EXPECT_TRUE(out.intersected);
    EXPECT_TRUE(out.all_walled);
  }
}

// Found by the random sequences (RiggedSimple seed 1 step 237, a zero-area face after a walled
// drill): the circle crosses both long edges of a needle twice. The crossings nearer the far
// corners (one float step apart) round to one bind position too; they become one vertex, so the
// kept part at the needle's far end is one triangle, not one plus a face with two corners at one
// point.
TEST(DrillTest, a_hole_inside_a_needle_makes_no_zero_area_face) {
  for (const bool wall : {false, true}) {
    SCOPED_TRACE(wall ? "walled" : "no wall");
    SurfaceMesh mesh = test::make_needle_fan();  // X (0,1,0); far corners at x = 1
    const std::vector<glm::vec3> posed = mesh.positions();
    Adjacency adj = Adjacency::build(mesh);
    // Axis along z through (0.2, 1): the circle of radius 0.1 crosses the needle at x = 0.1 and
    // x = 0.3, where both edges' crossings round to y = 1.
    DrillOptions options;
    options.wall = wall;
    const DrillResult r =
        drill_mesh(mesh, PosedMesh::at_positions(mesh, posed), Cylinder{{0.2f, 1, -1}, {0.2f, 1, 1}, 0.1f}, options);
    ASSERT_EQ(r.status, OpStatus::Ok);
    adj.apply(r.log);
    test::expect_adjacency_matches_rebuild(adj, mesh);
    test::expect_valid(mesh);
    for (const float x : {0.1f, 0.3f}) {
      std::size_t used = 0;  // used vertices where the needle is crossed
      for (std::uint32_t i = 0; i < mesh.vertex_count(); ++i)
        used += glm::distance(mesh.position(VertexId(i)), glm::vec3(x, 1, 0)) < 1e-6f &&
                !adj.vertex_faces(VertexId(i)).empty();
      EXPECT_EQ(used, 1u) << "both crossings of the needle at x = " << x << " are one vertex";
    }
    mesh.for_each_face([&](FaceId f, const Triangle& t) {
      const glm::dvec3 u(mesh.position(t[0])), v(mesh.position(t[1])), w(mesh.position(t[2]));
      EXPECT_GT(glm::length(glm::cross(v - u, w - u)), 0.0) << "face " << f.index << " has zero area";
    });
  }
}

// Found by the random sequences (zero-area faces after drills): a needle whose two long edges
// run from X to corners one float step apart. The circle crosses both edges nearer X than the
// far corners, where both crossings round to one bind position; they become one vertex, and the
// needle's kept tip (a face with two corners at one point) is not made.
TEST(DrillTest, a_rim_across_a_needle_makes_no_zero_area_face) {
  for (const bool indexed : {false, true}) {
    SCOPED_TRACE(indexed ? "indexed" : "scan");
    SurfaceMesh mesh = test::make_needle_fan();  // X (0,1,0); far corners at x = 1
    const std::vector<glm::vec3> posed = mesh.positions();
    Adjacency adj = Adjacency::build(mesh);
    // Axis along z through (1.3, 1): the circle of radius 0.9 crosses the needle at x = 0.4.
    const DrillResult r =
        drill_mesh(mesh, PosedMesh::at_positions(mesh, posed), Cylinder{{1.3f, 1, -1}, {1.3f, 1, 1}, 0.9f});
    ASSERT_EQ(r.status, OpStatus::Ok);
    adj.apply(r.log);
    test::expect_adjacency_matches_rebuild(adj, mesh);
    test::expect_valid(mesh);
    std::size_t at_tip = 0;  // used vertices where the needle is crossed
    for (std::uint32_t i = 0; i < mesh.vertex_count(); ++i)
      at_tip += glm::distance(mesh.position(VertexId(i)), glm::vec3(0.4f, 1, 0)) < 1e-6f &&
                !adj.vertex_faces(VertexId(i)).empty();
    EXPECT_EQ(at_tip, 1u) << "both crossings of the needle are one vertex";
    mesh.for_each_face([&](FaceId f, const Triangle& t) {
      const glm::dvec3 u(mesh.position(t[0])), v(mesh.position(t[1])), w(mesh.position(t[2]));
      EXPECT_GT(glm::length(glm::cross(v - u, w - u)), 0.0) << "face " << f.index << " has zero area";
      for (const VertexId c : t) EXPECT_GE(glm::distance(glm::vec2(mesh.position(c)), glm::vec2(1.3f, 1)), 0.9f * 0.99f);
    });
  }
}

// A vertex on the cylinder that the drill pinches is split before the rims are traced (without a
// wall); its copy is a new vertex, but the faces moved onto it keep their old edges. An old
// boundary edge from it to another old vertex on the cylinder is not rim: the rim stops there,
// where it joins the boundary the input already had.
TEST(DrillTest, an_old_boundary_edge_at_a_split_vertex_is_not_rim) {
  for (const bool indexed : {false, true}) {
    SCOPED_TRACE(indexed ? "indexed" : "scan");
    SurfaceMesh mesh;
    // The saddle of rim_through_a_saddle_vertex_leaves_no_pinched_vertex, opened between +x and +y:
    // the boundary edge v-w lies along the line where the cylinder touches z = 0.
    const VertexId v = mesh.add_vertex({0, 0, 0}), w = mesh.add_vertex({0.5f, 0, 0});
    const VertexId py = mesh.add_vertex({0, 1, -1}), mx = mesh.add_vertex({-1, 0, 1}), my = mesh.add_vertex({0, -1, -1}),
                   my2 = mesh.add_vertex({0.3f, -1, -1}), px = mesh.add_vertex({1, 0, 1});
    mesh.add_face(v, my, my2);  // untouched, lowest id: the -y wedge keeps v, the +y wedge gets the copy
    mesh.add_face(v, mx, my);
    mesh.add_face(v, my2, px);
    mesh.add_face(v, w, py);
    mesh.add_face(v, py, mx);
    const Adjacency before = Adjacency::build(mesh);
    const auto old_boundary = before.boundary_edges();
    ASSERT_TRUE(std::binary_search(old_boundary.begin(), old_boundary.end(), make_edge(v, w)));
    const std::vector<glm::vec3> posed = mesh.positions();
    const std::uint32_t old_count = static_cast<std::uint32_t>(mesh.vertex_count());
    const DrillResult r =
        drill_mesh(mesh, PosedMesh::at_positions(mesh, posed), Cylinder{{-2, 0, 0.6f}, {2, 0, 0.6f}, 0.6f});
    ASSERT_EQ(r.status, OpStatus::Ok);
    test::expect_valid(mesh);
    std::map<std::uint32_t, std::uint32_t> original;
    std::size_t splits = 0;
    for (const Edit& e : r.log.edits)
      if (const auto* sp = std::get_if<VertexSplit>(&e)) {
        original[sp->copy.index] = sp->original.index;
        ++splits;
      }
    EXPECT_EQ(splits, 1u) << "the saddle vertex is split";
    EXPECT_FALSE(r.holes.empty());
    auto base = [&](VertexId x) {
      const auto it = original.find(x.index);
      return VertexId(it == original.end() ? x.index : it->second);
    };
    for (const DrillHole& h : r.holes)
      for (std::size_t i = 0; i + 1 < h.rim.size() + (h.closed ? 1 : 0); ++i) {
        const VertexId a = base(h.rim[i]), b = base(h.rim[(i + 1) % h.rim.size()]);
        if (a.index >= old_count || b.index >= old_count) continue;
        EXPECT_FALSE(std::binary_search(old_boundary.begin(), old_boundary.end(), make_edge(a, b)))
            << "rim step " << h.rim[i].index << "->" << h.rim[(i + 1) % h.rim.size()].index
            << " is the old boundary edge " << a.index << "-" << b.index;
      }
  }
}

// Found by random drills with other seeds (SimpleSkin, seed 3 drill 23: a round hole with 31 rim
// edges of 32): an edge the cylinder only grazes (shallower than the tolerance, so not cut) at a
// crease. A ruling's point lay just beyond that edge in its triangle's plane and, at the crease,
// beyond it in the neighbour's plane too: no triangle took it. It is moved inside its triangle.
TEST(DrillTest, a_ruling_beyond_a_grazed_edge_keeps_its_rim_point) {
  const Model simple = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/models/SimpleSkin/SimpleSkin.gltf");
  const Cylinder c{{0.662097514f, 1.06322265f, 0.650242746f}, {0.376118004f, 1.6702919f, -0.334016979f}, 0.201499388f};
  for (const bool wall : {false, true})
    for (const bool indexed : {false, true}) {
      SCOPED_TRACE(std::string(wall ? "wall" : "no wall") + (indexed ? ", indexed" : ""));
      const Checked out = check_asset_drill(simple, c, wall, indexed);
      if (::testing::Test::HasFatalFailure()) return;
      EXPECT_EQ(out.round_holes, 1u) << "check_drill counts its rim edges";
    }
}

// A vertex lying just inside the cylinder (1% of r, a tenth of the rim spacing) had two edges
// crossed a hair from it: it went, and the far corners of its faces fanned to the two close
// crossings (needles; on a needle parent, degenerate triangles). It is now slid onto the
// cylinder and becomes a rim vertex; its bind position moves through its own skinning (here a
// translation between bind and posed space), and DrillResult::moved reports the posed one.
TEST(DrillTest, a_vertex_just_inside_the_cylinder_becomes_a_rim_vertex) {
  for (const bool indexed : {false, true}) {
    SCOPED_TRACE(indexed ? "indexed" : "scan");
    SurfaceMesh mesh = test::make_grid(8, 8);  // unit square, spacing 0.125
    const SurfaceMesh input = mesh;
    const glm::vec3 offset(0.3f, -0.2f, 0.1f);  // posed = bind + offset
    std::vector<glm::vec3> posed = mesh.positions();
    for (auto& p : posed) p += offset;
    const VertexId centre(4 * 9 + 4);  // at (0.5, 0.5)
    const float r = 0.2f;
    Cylinder c;
    // The axis 0.99 r from it, towards 200 degrees: the circle is tangent to no grid line there.
    const glm::vec3 toward(std::cos(3.49066f), std::sin(3.49066f), 0.0f);
    c.a = glm::vec3(0.5f, 0.5f, -1.0f) + 0.99f * r * toward + offset;
    c.b = glm::vec3(0.5f, 0.5f, 1.0f) + 0.99f * r * toward + offset;
    c.radius = r;
    PosedMesh at = PosedMesh::at_positions(mesh, posed);
    at.world = glm::translate(glm::mat4(1.0f), offset);  // new vertices go back by -offset
    at.no_unpose = false;
    const DrillResult res = drill_mesh(mesh, at, c, DrillOptions{});
    ASSERT_EQ(res.status, OpStatus::Ok);
    // No needle there: the faces with a corner within a rim spacing of where the vertex was keep
    // at least 10 degrees (without the snap: two crossings a hair apart, faces under 1.5).
    const glm::vec3 was = input.position(centre);
    const double spacing = 2.0 * r * std::sin(kPi / 32);
    mesh.for_each_face([&](FaceId f, const Triangle& t) {
      bool near = false;
      for (VertexId v : t) near |= glm::length(mesh.position(v) - was) < spacing;
      if (near) {
        EXPECT_GE(min_angle(mesh, t), 10.0) << "face " << f.index << " near the vertex";
      }
    });
    const auto it = std::find_if(res.moved.begin(), res.moved.end(), [&](const auto& m) { return m.v == centre; });
    ASSERT_NE(it, res.moved.end()) << "the vertex is moved";
    const glm::vec3 moved = it->posed;
    EXPECT_NEAR(glm::length(glm::vec2(moved - c.a)), r, 1e-5f) << "on the cylinder";
    EXPECT_NEAR(moved.z - offset.z, 0.0f, 1e-6f) << "slid in its own plane";
    EXPECT_LT(glm::length(mesh.position(centre) + offset - moved), 1e-5f) << "bind moved with posed";
    std::size_t moves = 0;
    for (const Edit& e : res.log.edits)
      if (const auto* m = std::get_if<VertexMoved>(&e)) moves += m->v == centre;
    EXPECT_EQ(moves, 1u) << "logged as VertexMoved";
    ASSERT_EQ(res.holes.size(), 1u);
    EXPECT_NE(std::find(res.holes[0].rim.begin(), res.holes[0].rim.end(), centre), res.holes[0].rim.end())
        << "the vertex is on the rim";
    Adjacency adj = Adjacency::build(input);
    adj.apply(res.log);
    test::expect_adjacency_matches_rebuild(adj, mesh);
    test::expect_valid(mesh, 2);
  }
}

// The snap leaves a vertex on the mesh's border where it is: a primitive split at a material
// seam keeps its own copy of every seam vertex, and the other primitive, drilled on its own,
// would not slide its copy the same way (a crack along the seam). Here X is the apex of a
// three-quarter fan (its two outer spokes are border edges), just inside the cylinder, with
// spokes crossed a hair from it: an inner vertex there would be slid (test above).
TEST(DrillTest, a_border_vertex_just_inside_the_cylinder_stays) {
  SurfaceMesh mesh;
  const VertexId x = mesh.add_vertex({0.0f, 0.0f, 0.0f});
  std::vector<VertexId> ring;
  for (int i = 0; i <= 9; ++i) {
    const float a = static_cast<float>(i) * static_cast<float>(kPi) / 6.0f;  // 0 to 270 degrees
    ring.push_back(mesh.add_vertex({0.125f * std::cos(a), 0.125f * std::sin(a), 0.0f}));
  }
  for (std::size_t i = 0; i + 1 < ring.size(); ++i) mesh.add_face(x, ring[i], ring[i + 1]);
  const SurfaceMesh input = mesh;
  const float r = 0.2f;
  // The axis 0.99 r from X into the missing quarter: the spokes towards 120 and 150 degrees
  // leave the circle within 1% of r of X (half a rim spacing is 0.02).
  const glm::vec3 toward(std::cos(1.75f * static_cast<float>(kPi)), std::sin(1.75f * static_cast<float>(kPi)), 0.0f);
  Cylinder c{glm::vec3(0.0f, 0.0f, -1.0f) + 0.99f * r * toward, glm::vec3(0.0f, 0.0f, 1.0f) + 0.99f * r * toward, r};
  const DrillResult res = drill_mesh(mesh, PosedMesh::at_positions(mesh), c);
  ASSERT_EQ(res.status, OpStatus::Ok);
  for (const auto& m : res.moved) {
    EXPECT_NE(m.v, x) << "the border vertex was slid";
  }
  for (const Edit& e : res.log.edits) {
    if (const auto* m = std::get_if<VertexMoved>(&e)) {
      EXPECT_NE(m->v, x) << "a move of the border vertex is logged";
    }
  }
  EXPECT_EQ(mesh.position(x), input.position(x));
  Adjacency adj = Adjacency::build(input);
  adj.apply(res.log);
  test::expect_adjacency_matches_rebuild(adj, mesh);
}

// Found by the random sequences (SimpleSkin seed 4 step 282, a drill without wall): a part cut
// down to a speck 2e-5 across at coordinates about 1.3 got a drill of radius 3.1e-7 (1% of the
// speck) with 48 rim edges: rim points 4e-8 apart, a third of a float step there, so the bind
// positions of a rim's new face rounded onto one line (three distinct corners, zero area). Such
// a cylinder is refused: its rim spacing must exceed the drill's absolute tolerance (1e-6 of the
// axis' coordinates); just above that every new face keeps a non-zero area.
TEST(DrillTest, a_rim_finer_than_float_precision_is_refused) {
  SurfaceMesh mesh = test::make_grid(4, 4);
  const glm::vec3 at(0.743281424f, 1.24779034f, -0.000512723869f);
  for (auto& p : mesh.positions()) p = at + 2e-5f * (p - glm::vec3(0.5f, 0.5f, 0.0f));
  Cylinder c;
  c.a = at + glm::vec3(1e-7f, 2e-7f, -1e-5f);
  c.b = at + glm::vec3(1e-7f, 2e-7f, 1e-5f);
  DrillOptions options;
  options.min_rim_edges = 48;
  for (const float radius : {3.1e-7f, 1e-6f, 2e-6f}) {
    c.radius = radius;
    SurfaceMesh copy = mesh;
    EXPECT_THROW(drill_mesh(copy, PosedMesh::at_positions(copy), c, options), Error) << "radius " << radius;
    EXPECT_EQ(copy.faces(), mesh.faces());
  }
  const double scale = glm::length(glm::dvec3(c.a)) + glm::length(glm::dvec3(c.b)) + 2e-5;
  c.radius = static_cast<float>(2.0 * 1e-6 * scale / (2.0 * std::sin(kPi / 48)));
  SurfaceMesh copy = mesh;
  const DrillResult r = drill_mesh(copy, PosedMesh::at_positions(copy), c, options);
  ASSERT_EQ(r.status, OpStatus::Ok);
  for (const Edit& e : r.log.edits)
    if (const auto* fa = std::get_if<FaceAdded>(&e)) {
      const glm::dvec3 x(copy.position(fa->vertices[0])), y(copy.position(fa->vertices[1])),
          z(copy.position(fa->vertices[2]));
      EXPECT_GT(glm::length(glm::cross(y - x, z - x)), 0.0) << "new face " << fa->f.index << " has zero area";
    }
  test::expect_valid(copy, 2);
}

// A coarse mesh (one quad) with holes across its diagonal, near its corners and its sides: the
// kept part of each crossed edge gets points graded away from the crossings, so a far corner no
// longer fans to rim points a spacing apart and rim points do not sit next to a long kept edge.
// Without them 7% of the new triangles were under 5 degrees (2 263 of 32 212), now 3%.
TEST(DrillTest, holes_in_a_coarse_quad_leave_few_needles) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> along(0.1f, 0.9f), radius(0.02f, 0.08f);
  std::size_t added = 0, thin = 0, crossed = 0, graded = 0;
  for (int i = 0; i < 200; ++i) {
    SurfaceMesh mesh = test::make_grid(1, 1);
    const float x = along(rng), r = radius(rng), y = i % 2 ? 1.0f - x : x;  // on either diagonal
    const std::size_t faces = mesh.face_slots(), vertices = mesh.vertex_count();
    const Cylinder c{{x, y, -1}, {x, y, 1}, r};
    const DrillResult d = drill_mesh(mesh, PosedMesh::at_positions(mesh), c);
    ASSERT_EQ(d.status, OpStatus::Ok);
    test::expect_valid(mesh, 2);
    mesh.for_each_face([&](FaceId f, const Triangle& t) {
      if (f.index < faces) return;
      ++added;
      thin += min_angle(mesh, t) < 5.0;
    });
    const Axis ax(c);
    for (const auto& e : d.log.edits)
      if (const auto* a = std::get_if<VertexAdded>(&e); a && !a->from[2].valid()) {
        const bool on = std::abs(ax.rho(mesh.position(a->v)) - ax.r) <= 0.01 * ax.r;
        crossed += on;
        graded += !on && a->v.index >= vertices;
      }
  }
  EXPECT_GT(graded, crossed) << "the kept parts of crossed edges get points";
  EXPECT_LE(thin, added * 4 / 100) << "new triangles under 5 degrees";
  std::printf("under 5 degrees: %zu of %zu new triangles; %zu crossings, %zu graded points\n", thin, added, crossed, graded);
}

}  // namespace deepcut

