// SPDX-License-Identifier: MIT
// The drill's rim in special places: through a saddle vertex, at an end plane's corner, rims
// meeting at a vertex, needles, grazed edges, vertices a hair from the side, float precision.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <random>
#include <string>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/ops/drill.h"
#include "deepcut/core/spatial_index.h"
#include "drill_checks.h"
#include "fixtures.h"
#include "geometry/predicates.h"
#include "ops/drill/rim_faces.h"
#include "ops/drill/rim_insertion.h"
#include "tools.h"

namespace deepcut {
namespace {

using geometry::kPi;
using test::Axis;
using test::check_asset_drill;
using test::Checked;
using test::min_angle;

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

// Drills `mesh` at rest by `cyl` (expecting success) with an adjacency following the drill's
// log, checks the adjacency against a rebuild and the mesh's validity, and returns the adjacency.
Adjacency drill_with_checks(SurfaceMesh& mesh, const Cylinder& cyl, const DrillOptions& options) {
  const std::vector<glm::vec3> posed = mesh.positions();
  Adjacency adj = Adjacency::build(mesh);
  const DrillResult r = drill_mesh(mesh, PosedMesh::at_positions(mesh, posed), cyl, options);
  test::follow_checked(adj, mesh, r.status, r.log);
  return adj;
}

// How many vertices within 1e-6 of `p` some face still uses.
std::size_t used_vertices_at(const SurfaceMesh& mesh, const Adjacency& adj, const glm::vec3& p) {
  std::size_t used = 0;
  for (std::uint32_t i = 0; i < mesh.vertex_count(); ++i)
    used += glm::distance(mesh.position(VertexId(i)), p) < 1e-6f && !adj.vertex_faces(VertexId(i)).empty();
  return used;
}

// One drill of an asset model: the model and the cylinder.
struct AssetDrill {
  const Model* model;
  Cylinder c;
};

}  // namespace

// A saddle vertex lying on the cylinder's side, its surface rising into the cylinder towards +x
// and -x and falling away towards +y and -y. The kept surface is two wedges (around +y and -y)
// that meet only at that vertex: each gets its own vertex (no pinched vertex, two used vertices
// at the saddle point), with and without a wall, and with the spatial index.
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

// A vertex off the cylinder whose faces the drill parts: the face between them is degenerate
// (its corners on one line into the cylinder), so it is removed with no kept part, and the two
// faces beside it no longer share an edge at the vertex. Off the rim, the vertex is still split
// (one vertex per fan).
TEST(DrillTest, a_corner_bared_off_the_rim_is_split_where_its_fans_part) {
  SurfaceMesh mesh;
  const VertexId v = mesh.add_vertex({2, 0, 0}), a = mesh.add_vertex({1.5f, 1, 0});
  const VertexId b = mesh.add_vertex({1, 0, 0}), c = mesh.add_vertex({0, 0, 0});
  const VertexId d = mesh.add_vertex({1.5f, -1, 0});
  mesh.add_face(v, a, b);
  mesh.add_face(v, b, c);  // degenerate: v, b and c on the x axis
  mesh.add_face(v, c, d);
  const std::vector<glm::vec3> posed = mesh.positions();
  const DrillResult r =
      drill_mesh(mesh, PosedMesh::at_positions(mesh, posed), Cylinder{{0, 0, -2}, {0, 0, 2}, 0.5f});
  ASSERT_EQ(r.status, OpStatus::Ok);
  EXPECT_TRUE(test::pinched_vertices(mesh).empty());
  std::size_t splits = 0;
  for (const Edit& e : r.log.edits)
    if (const auto* sp = std::get_if<VertexSplit>(&e)) splits += sp->original == v ? 1 : 0;
  EXPECT_EQ(splits, 1u) << "the bared corner is split";
}

// Drills whose D-shaped rim has a corner where its straight part (on the end plane at B) meets
// its arc, within a rim spacing of a crossing or just outside the triangle the rim bends in
// (random drills of the Fox and the cactus, DEEPCUT_DRILL_SEED 1 to 3). The corner stays a rim
// point: every check_drill invariant holds (no kept surface inside the cylinder, which a chord
// between the two parts would leave), with and without a wall.
TEST(DrillTest, rim_corner_on_an_end_plane_is_kept) {
  const Model cactus = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  const Model fox = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/models/Fox/Fox.glb");
  const AssetDrill cases[] = {
      {&fox, {{5.43106747f, 43.0290604f, 0.525301933f}, {9.20565319f, 15.536129f, -40.5920792f}, 14.184804f}},
      {&cactus, {{1.30557191f, 10.2793427f, -1.0248698f}, {-1.61410236f, 4.22243118f, 1.19152451f}, 0.477234244f}},
      {&cactus, {{1.89666462f, 5.35040665f, -1.75495446f}, {-0.600944042f, 2.68694258f, 0.668461919f}, 0.682955205f}}};
  for (const AssetDrill& k : cases) {
    expect_asset_drill_hits_and_walls(*k.model, k.c, false);
    if (::testing::Test::HasFatalFailure()) return;
  }
}

// Two rims meeting at one vertex on the cylinder (a cactus drill): each incoming rim edge goes on
// with the outgoing one of its own fan, so the rims do not cross there. The drill keeps every
// check_drill invariant (each rim step is an edge of the mesh after the pinch split) and, with a
// wall, walls every hole; with and without the spatial index.
TEST(DrillTest, rims_meeting_at_a_vertex_follow_their_own_fans) {
  const Model cactus = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  const Cylinder c{{7.87602472f, 6.90400934f, -5.91235971f}, {-9.16912842f, -1.46460295f, 6.17348909f}, 0.876988471f};
  expect_asset_drill_hits_and_walls(cactus, c, true);
}

// Walled drills of closed input that close every hole:
// - cactus: two rims of one shell touch at a vertex on the cylinder; the hole loop still gets
//   its outer loop, though the winding number at the shared vertex is 0 or 1 by rounding.
// - RiggedSimple: a layer that only clips the cylinder's end circle cuts a thin lens; its arc
//   gets a point, so the hole has an area (the straight part and its chord alone would be a
//   slit no wall can close).
TEST(DrillTest, walls_close_rims_that_touch_and_thin_lenses_at_an_end) {
  const Model cactus = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  const Model simple = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/models/RiggedSimple/RiggedSimple.gltf");
  const AssetDrill cases[] = {
      {&cactus, {{-1.70535243f, 9.63420868f, 4.90398598f}, {1.43953931f, 4.25307465f, -5.2903614f}, 0.674046218f}},
      {&simple, {{2.87141538f, -0.539521337f, 3.19743991f}, {-1.04472518f, 0.391219884f, -4.29873753f}, 0.587547898f}}};
  for (const AssetDrill& k : cases) {
    const Checked out = check_asset_drill(*k.model, k.c, true, false);
    if (::testing::Test::HasFatalFailure()) return;
    EXPECT_TRUE(out.intersected);
    EXPECT_TRUE(out.all_walled);
  }
}

// A circle inside a needle, crossing both its long edges twice. The crossings nearer the far
// corners (one float step apart) round to one bind position; they are one vertex, so the kept
// part at the needle's far end is one triangle and no face has zero area (a face with two
// corners at one point), with and without a wall.
TEST(DrillTest, a_hole_inside_a_needle_makes_no_zero_area_face) {
  for (const bool wall : {false, true}) {
    SCOPED_TRACE(wall ? "walled" : "no wall");
    SurfaceMesh mesh = test::make_needle_fan();  // X (0,1,0); far corners at x = 1
    // Axis along z through (0.2, 1): the circle of radius 0.1 crosses the needle at x = 0.1 and
    // x = 0.3, where both edges' crossings round to y = 1.
    DrillOptions options;
    options.wall = wall;
    const Adjacency adj = drill_with_checks(mesh, Cylinder{{0.2f, 1, -1}, {0.2f, 1, 1}, 0.1f}, options);
    for (const float x : {0.1f, 0.3f})
      EXPECT_EQ(used_vertices_at(mesh, adj, {x, 1, 0}), 1u)
          << "both crossings of the needle at x = " << x << " are one vertex";
    mesh.for_each_face([&](FaceId f, const Triangle& t) {
      const glm::dvec3 u(mesh.position(t[0])), v(mesh.position(t[1])), w(mesh.position(t[2]));
      EXPECT_GT(glm::length(glm::cross(v - u, w - u)), 0.0) << "face " << f.index << " has zero area";
    });
  }
}

// A needle whose two long edges run from X to corners one float step apart, its tip kept: the
// circle crosses both edges nearer X than the far corners, where both crossings round to one
// bind position. They are one vertex, the needle's tip (a face with two corners at one point)
// is not made: no face has zero area, and none reaches inside the circle.
TEST(DrillTest, a_rim_across_a_needle_makes_no_zero_area_face) {
  for (const bool indexed : {false, true}) {
    SCOPED_TRACE(indexed ? "indexed" : "scan");
    SurfaceMesh mesh = test::make_needle_fan();  // X (0,1,0); far corners at x = 1
    // Axis along z through (1.3, 1): the circle of radius 0.9 crosses the needle at x = 0.4.
    const Adjacency adj = drill_with_checks(mesh, Cylinder{{1.3f, 1, -1}, {1.3f, 1, 1}, 0.9f}, DrillOptions{});
    EXPECT_EQ(used_vertices_at(mesh, adj, {0.4f, 1, 0}), 1u) << "both crossings of the needle are one vertex";
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

// A cylinder through two neighbouring grid vertices a and b: the old edge a-b lies inside it by
// less than the tolerance (its sagitta), so it is not crossed; the face inside it is removed, the
// one outside is kept, and the rim runs along a-b. That step is a half-edge between two old
// vertices, a rim step only because the face across it was removed (the removed faces' rim
// half-edges are filed for it): the hole is one closed rim through a then b, and the mesh's
// boundary is the grid's outline and that rim, nothing else.
TEST(DrillTest, a_rim_along_an_old_edge_closes_the_hole) {
  constexpr int n = 64;  // spacing 1/64: sagitta 1.5e-4 of r 0.2, under the tolerance (4e-4)
  SurfaceMesh mesh = test::make_grid(n, n);
  const VertexId a(static_cast<std::uint32_t>(n / 2 * (n + 1) + n / 2)), b(a.index + 1);
  const glm::vec3 pa = mesh.position(a), pb = mesh.position(b);
  ASSERT_EQ(pa, glm::vec3(0.5f, 0.5f, 0.0f));
  ASSERT_EQ(pb, glm::vec3(0.5f + 1.0f / n, 0.5f, 0.0f));
  // The axis along z, below a-b on its perpendicular bisector, at distance r from both.
  const float radius = 0.2f, half = 0.5f / n;
  const float cy = 0.5f - std::sqrt(radius * radius - half * half);
  const glm::vec3 centre(pa.x + half, cy, 0.0f);
  const Cylinder cyl{centre - glm::vec3(0, 0, 1), centre + glm::vec3(0, 0, 1), glm::distance(centre, pa)};
  const std::size_t outline = 4 * n;  // the grid's boundary edges
  const Adjacency before = Adjacency::build(mesh);
  ASSERT_EQ(before.boundary_edges().size(), outline);
  const std::vector<glm::vec3> posed = mesh.positions();
  const DrillResult r = drill_mesh(mesh, PosedMesh::at_positions(mesh, posed), cyl);
  ASSERT_EQ(r.status, OpStatus::Ok);
  test::expect_valid(mesh);
  ASSERT_EQ(r.holes.size(), 1u);
  const DrillHole& h = r.holes[0];
  EXPECT_TRUE(h.closed);
  EXPECT_EQ(std::abs(h.winding), 1);
  const Adjacency adj = Adjacency::build(mesh);
  EXPECT_EQ(adj.edge_faces(a, b).size(), 1u) << "the face outside a-b is kept, the one inside removed";
  const auto boundary = adj.boundary_edges();
  EXPECT_EQ(boundary.size(), outline + h.rim.size()) << "the boundary is the outline and the rim";
  std::size_t along_ab = 0;
  for (std::size_t i = 0; i < h.rim.size(); ++i) {
    const VertexId u = h.rim[i], v = h.rim[(i + 1) % h.rim.size()];
    EXPECT_TRUE(std::binary_search(boundary.begin(), boundary.end(), make_edge(u, v)))
        << "rim step " << u.index << "->" << v.index << " is not a boundary edge";
    along_ab += make_edge(u, v) == make_edge(a, b);
  }
  EXPECT_EQ(along_ab, 1u) << "the rim runs along the old edge a-b once";
}

// A SimpleSkin drill that only grazes an edge at a crease (shallower than the tolerance, so it is
// not cut): a ruling's point lies just beyond that edge in its triangle's plane and, at the
// crease, beyond it in the neighbour's plane too. It moves inside its triangle, so the hole is
// round with all its 32 rim edges (check_drill counts them), with and without a wall and the
// spatial index.
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

// A vertex lying just inside the cylinder (1% of r, a tenth of the rim spacing), two of its
// edges crossed a hair from it: it is slid onto the cylinder and becomes a rim vertex, so the far
// corners of its faces do not fan to two close crossings (needles). Its bind position moves
// through its own skinning (here a translation between bind and posed space), and
// DrillResult::moved reports the posed one.
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

// The snap's pass over the candidates' corners marks those deep inside, and marks a vertex it
// slides again: a vertex 1% of r inside the side (deep inside, beyond twice the tolerance of 0.2%
// of r, and within the snap band, a tenth of a rim spacing or 2% of r) slid onto the cylinder is
// no longer deep. Every candidate's deep corners are what deep_vertex says of its corners once
// the vertex has slid (what judging each corner afresh gives), so a face at the vertex with its
// two other corners deep inside is not removed whole as a face deep inside: it is removed with no
// kept part at the vertex and bares it (RimInsertion::bared), once; no other face bares it here.
// Without the second mark both checks fail (the slid vertex stays marked deep).
TEST(DrillTest, a_vertex_slid_out_of_deep_inside_is_bared_by_its_removed_faces) {
  SurfaceMesh mesh = test::make_grid(8, 8);  // unit square, spacing 0.125
  const std::vector<glm::vec3> input = mesh.positions();
  const VertexId centre(4 * 9 + 4);  // at (0.5, 0.5)
  const float r = 0.2f;
  // The axis 0.99 r from it, towards 200 degrees (as in
  // a_vertex_just_inside_the_cylinder_becomes_a_rim_vertex).
  const glm::vec3 toward(std::cos(3.49066f), std::sin(3.49066f), 0.0f);
  const Cylinder c{glm::vec3(0.5f, 0.5f, -1.0f) + 0.99f * r * toward,
                   glm::vec3(0.5f, 0.5f, 1.0f) + 0.99f * r * toward, r};
  const drill::CylinderFrame cyl = drill::CylinderFrame::make(c, DrillOptions{});
  drill::PosedOverlay posed(input, drill::Unposer());
  ASSERT_TRUE(drill::deep_vertex(cyl, posed, centre)) << "deep inside before the snap";
  const TriangleGrid grid = TriangleGrid::build(mesh, input);
  MeshEditor editor(mesh);
  const std::vector<FaceId> candidates = drill::find_candidates(mesh, cyl, posed, grid);
  std::vector<std::uint8_t> deep_corners;
  drill::snap_shallow_vertices(editor, cyl, posed, candidates, deep_corners);
  ASSERT_TRUE(posed.is_moved(centre)) << "the vertex is slid";
  EXPECT_FALSE(drill::deep_vertex(cyl, posed, centre)) << "on the cylinder";
  ASSERT_EQ(deep_corners.size(), candidates.size());
  std::vector<FaceId> others_deep;  // faces at the vertex whose two other corners lie deep inside
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const Triangle& t = mesh.face(candidates[i]);
    unsigned fresh = 0, at = 3;
    for (unsigned k = 0; k < 3; ++k) {
      fresh |= unsigned(drill::deep_vertex(cyl, posed, t[k])) << k;
      if (t[k] == centre) at = k;
    }
    EXPECT_EQ(unsigned(deep_corners[i]), fresh)
        << "candidate " << i << " (face " << candidates[i].index << ")";
    if (at < 3 && (fresh | 1u << at) == 7u) others_deep.push_back(candidates[i]);
  }
  // Without the second mark these would be removed whole (three corners marked deep), the vertex
  // not bared.
  ASSERT_FALSE(others_deep.empty());
  const drill::RimInsertion inserted = drill::insert_rim(editor, cyl, posed, candidates, deep_corners);
  for (const FaceId f : others_deep) EXPECT_TRUE(mesh.is_deleted(f)) << "face " << f.index;
  EXPECT_EQ(static_cast<std::size_t>(std::count(inserted.bared.begin(), inserted.bared.end(), centre)),
            others_deep.size());
}

// Candidates wholly outside the solid, a tolerance clear of it (clear_of_cylinder), are left as
// they are without a look at their edges: a second sheet just beyond the end plane, a small
// triangle just outside the side (both within the candidates' reach, each by more than the
// tolerance of 0.2% of r) and the faces of the drilled sheet around the hole keep their corners,
// positions and texture coordinates, and no edit removes them. Fails if the drill removes them.
TEST(DrillTest, faces_clear_of_the_cylinder_near_the_hole_are_left_as_they_are) {
  SurfaceMesh mesh = test::make_grid(8, 8);  // unit square at z = 0, spacing 0.125
  const std::size_t sheet_faces = mesh.face_slots();
  const float r = 0.2f;
  const Cylinder c{{0.5f, 0.5f, -1.0f}, {0.5f, 0.5f, 1.0f}, r};
  // The same sheet again, 0.01 (25 tolerances) beyond the end plane at z = 1.
  const std::uint32_t lid_first = mesh.vertex_count();
  for (std::uint32_t v = 0; v < lid_first; ++v)
    mesh.add_vertex(mesh.position(VertexId(v)) + glm::vec3(0, 0, 1.01f));
  for (std::uint32_t f = 0; f < sheet_faces; ++f) {
    const Triangle t = mesh.face(FaceId(f));
    mesh.add_face(VertexId(t[0].index + lid_first), VertexId(t[1].index + lid_first),
                  VertexId(t[2].index + lid_first));
  }
  const std::size_t lid_faces = mesh.face_slots();
  // A triangle half way up, its nearest corner 0.005 (12 tolerances) outside the side.
  const VertexId near = mesh.add_vertex({0.5f + r + 0.005f, 0.5f, 0.5f});
  const VertexId far0 = mesh.add_vertex({0.5f + r + 0.025f, 0.48f, 0.5f});
  const VertexId far1 = mesh.add_vertex({0.5f + r + 0.025f, 0.52f, 0.5f});
  mesh.add_face(near, far0, far1);
  const SurfaceMesh before = mesh;
  const std::vector<glm::vec3> input = mesh.positions();
  // The candidates clear of the cylinder, as the drill judges them (no vertex slides here).
  const drill::CylinderFrame cyl = drill::CylinderFrame::make(c, DrillOptions{});
  const drill::PosedOverlay posed(input, drill::Unposer());
  std::vector<FaceId> clear;
  std::size_t in_sheet = 0, in_lid = 0, lone = 0;
  for (const FaceId f : drill::find_candidates(mesh, cyl, posed, TriangleGrid::build(mesh, input))) {
    const Triangle& t = mesh.face(f);
    const glm::dvec3 corner[3] = {posed(t[0]), posed(t[1]), posed(t[2])};
    if (!drill::clear_of_cylinder(cyl, corner)) continue;
    clear.push_back(f);
    (f.index < sheet_faces ? in_sheet : f.index < lid_faces ? in_lid : lone) += 1;
  }
  EXPECT_GT(in_sheet, 0u);
  EXPECT_GT(in_lid, 0u);
  EXPECT_EQ(lone, 1u);
  const DrillResult res = drill_mesh(mesh, PosedMesh::at_positions(mesh, input), c);
  ASSERT_EQ(res.status, OpStatus::Ok);
  EXPECT_TRUE(res.moved.empty());
  std::vector<bool> is_clear(before.face_slots(), false);
  const auto& uv = mesh.corner_attrs().get<glm::vec2>(attr::kUv0);
  const auto& uv_before = before.corner_attrs().get<glm::vec2>(attr::kUv0);
  for (const FaceId f : clear) {
    is_clear[f.index] = true;
    ASSERT_FALSE(mesh.is_deleted(f)) << "face " << f.index;
    EXPECT_EQ(mesh.face(f), before.face(f)) << "face " << f.index;
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(mesh.position(mesh.face(f)[k]), before.position(before.face(f)[k])) << "face " << f.index;
      EXPECT_EQ(uv[3 * f.index + k], uv_before[3 * f.index + k]) << "face " << f.index;
    }
  }
  for (const Edit& e : res.log.edits)
    if (const auto* fr = std::get_if<FaceRemoved>(&e)) {
      EXPECT_FALSE(fr->f.index < is_clear.size() && is_clear[fr->f.index])
          << "face " << fr->f.index << " removed";
    }
}

// A speck 2e-5 across at coordinates about 1.3, drilled with 48 rim edges at radii from 1% of
// the speck (rim points 4e-8 apart, a third of a float step there, where the bind positions of a
// new face would round onto one line). A cylinder whose rim spacing does not exceed the drill's
// absolute tolerance (1e-6 of the axis' coordinates) is refused and leaves the mesh as it was;
// just above that every new face keeps a non-zero area.
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
// longer fans to rim points a spacing apart and rim points do not sit next to a long kept edge:
// at most 4% of the new triangles are under 5 degrees (7% without the graded points).
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
  EXPECT_GT(graded, crossed) << "the kept parts of crossed edges get points: " << graded << " for " << crossed
                             << " crossings";
  EXPECT_LE(thin, added * 4 / 100) << thin << " of " << added << " new triangles under 5 degrees";
}

// The ruling windows take the corners' angles from window_theta, which must stay within 1.7e-6 of
// theta (the windows' margin over any ruling that can give a point is about 0.015): on a sweep
// of a full turn (the error's peaks lie near ratios 0.88 of the octants), the four diagonals,
// the half-axes, y = -0 behind the axis, random points round tilted axes at scales far apart,
// and at the axis' start.
TEST(DrillTest, window_theta_is_theta_within_its_bound) {
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  DrillOptions options;
  for (int axis = 0; axis < 8; ++axis) {
    const glm::vec3 a(float(unit(rng)), float(unit(rng)), float(unit(rng)));
    const glm::vec3 d = glm::normalize(glm::vec3(float(unit(rng)), float(unit(rng)), float(unit(rng))));
    const drill::CylinderFrame cyl = drill::CylinderFrame::make({a, a + 3.0f * d, 0.25f}, options);
    auto expect_close = [&](const glm::dvec3& p) {
      const double diff = std::remainder(cyl.window_theta(p) - cyl.theta(p), 2.0 * kPi);
      EXPECT_LE(std::abs(diff), 1.7e-6) << p.x << " " << p.y << " " << p.z;
    };
    const int sweep = axis == 0 ? 100000 : 4000;
    for (int i = 0; i < sweep; ++i) {
      const double th = 2.0 * kPi * (i + 0.5) / sweep - kPi;
      expect_close(cyl.a + 0.7 * (std::cos(th) * cyl.u + std::sin(th) * cyl.w) + 0.5 * cyl.d);
    }
    for (int i = 0; i < 2000; ++i) {
      const double scale = std::pow(10.0, 3.0 * unit(rng));
      expect_close(cyl.a + scale * glm::dvec3(unit(rng), unit(rng), unit(rng)));
    }
    for (const glm::dvec3& dir :
         {cyl.u, -cyl.u, cyl.w, -cyl.w, cyl.u + cyl.w, cyl.u - cyl.w, -cyl.u + cyl.w, -cyl.u - cyl.w})
      expect_close(cyl.a + 0.7 * dir + 1.5 * cyl.d);
    EXPECT_EQ(cyl.window_theta(cyl.a), 0.0);  // on the axis: 0 (any angle gives a whole window there)
  }
}

// Behind the axis with y = -0, window_theta takes atan2's sign: -pi, not +pi (a frame whose w is
// exactly +z, so a point on the plane z = 0 has y = -0 when it is made so).
TEST(DrillTest, window_theta_takes_atan2s_sign_at_minus_zero) {
  DrillOptions options;
  const drill::CylinderFrame cyl = drill::CylinderFrame::make({{0, 0, 0}, {0, 3, 0}, 0.25f}, options);
  for (const double z : {0.0, -0.0}) {
    const glm::dvec3 p = cyl.a - 0.5 * cyl.u + glm::dvec3(0, 0, z);
    EXPECT_EQ(std::signbit(cyl.window_theta(p)), std::signbit(cyl.theta(p))) << cyl.theta(p);
  }
}

}  // namespace deepcut
