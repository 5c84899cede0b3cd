// SPDX-License-Identifier: MIT
#include "deepcut/core/ops/cut.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <random>
#include <string>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/validate.h"
#include "fixtures.h"
#include "ops/common/posed_overlay.h"
#include "ops/cut/caps.h"
#include "ops/cut/classify.h"
#include "ops/cut/face_lists.h"
#include "tools.h"

namespace deepcut {
namespace {

double signed_distance(const glm::vec3& p, const Plane& plane) {
  return glm::dot(glm::dvec3(p) - glm::dvec3(plane.point), glm::normalize(glm::dvec3(plane.normal)));
}

// Directed-edge census of a face set: closed and consistently oriented means every directed edge
// appears once and its reverse once.
struct EdgeCensus {
  std::size_t boundary = 0, inconsistent = 0;
};
EdgeCensus census(const SurfaceMesh& mesh, const std::vector<FaceId>& faces) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (FaceId f : faces) {
    const auto& t = mesh.face(f);
    for (int k = 0; k < 3; ++k) ++directed[{t[k].index, t[(k + 1) % 3].index}];
  }
  EdgeCensus c;
  for (const auto& [e, n] : directed) {
    const auto it = directed.find({e.second, e.first});
    if (n > 1) ++c.inconsistent;
    if (it == directed.end()) ++c.boundary;
  }
  return c;
}

double volume_of(const SurfaceMesh& mesh, const std::vector<FaceId>& faces) {
  double v = 0.0;
  for (FaceId f : faces) {
    const auto& t = mesh.face(f);
    const glm::dvec3 a(mesh.position(t[0])), b(mesh.position(t[1])), c(mesh.position(t[2]));
    v += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  return v;
}

Plane random_plane(const BoundingBox& box, std::mt19937& rng) {
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  glm::vec3 n;
  do n = {gauss(rng), gauss(rng), gauss(rng)};
  while (glm::length(n) < 1e-3f);
  const glm::vec3 p = box.min + (box.max - box.min) * glm::vec3(0.1f + 0.8f * u01(rng), 0.1f + 0.8f * u01(rng), 0.1f + 0.8f * u01(rng));
  return {p, n};
}

// All the invariants of one mesh-level cut on bind positions.
void check_cut(const SurfaceMesh& input, const Plane& plane, const CutOptions& options, std::size_t joints) {
  SurfaceMesh mesh = input;
  const Adjacency before = Adjacency::build(input);
  const bool closed = before.boundary_edges().empty() && before.nonmanifold_edges().empty();
  const double size = input.bounds().diagonal();
  const double tol = options.relative_tolerance * size;
  Adjacency adj = before;
  const CutResult r = cut_mesh(mesh, mesh.positions(), plane, options);
  if (r.status == OpStatus::NoIntersection) {
    EXPECT_TRUE(r.log.empty());
    EXPECT_EQ(mesh.face_count(), input.face_count());
    return;
  }
  adj.apply(r.log);
  test::expect_adjacency_matches_rebuild(adj, mesh);
  test::expect_valid(mesh, joints);
  // No triangle has corners strictly on both sides.
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    bool pos = false, neg = false;
    for (auto v : t) {
      const double d = signed_distance(mesh.position(v), plane);
      pos |= d > tol * 1.01 + 1e-7 * size;
      neg |= d < -tol * 1.01 - 1e-7 * size;
    }
    ASSERT_FALSE(pos && neg) << "face " << f.index << " straddles the plane";
  });
  // New boundary edges lie on the plane; the others are pieces of the input's boundary edges.
  // Origin of each vertex: itself, or the input edge it was split from (through copies too).
  std::vector<std::array<std::uint32_t, 2>> origin(mesh.vertex_count());
  for (std::uint32_t v = 0; v < input.vertex_count(); ++v) origin[v] = {v, v};
  for (const Edit& e : r.log.edits) {
    if (const auto* a = std::get_if<VertexAdded>(&e)) origin[a->v.index] = {origin[a->from[0].index][0], origin[a->from[1].index][0]};
    if (const auto* sp = std::get_if<VertexSplit>(&e)) origin[sp->copy.index] = origin[sp->original.index];
  }
  const auto old_boundary = before.boundary_edges();
  for (const Edge& e : adj.boundary_edges()) {
    std::vector<std::uint32_t> ends = {origin[e.a.index][0], origin[e.a.index][1], origin[e.b.index][0], origin[e.b.index][1]};
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    if (ends.size() == 2 && std::binary_search(old_boundary.begin(), old_boundary.end(), make_edge(VertexId(ends[0]), VertexId(ends[1]))))
      continue;
    ASSERT_LE(std::abs(signed_distance(mesh.position(e.a), plane)), tol + 1e-6 * size);
    ASSERT_LE(std::abs(signed_distance(mesh.position(e.b), plane)), tol + 1e-6 * size);
  }
  for (VertexId v : r.rim_vertices) ASSERT_LE(std::abs(signed_distance(mesh.position(v), plane)), tol + 1e-6 * size);
  if (!options.cap && options.keep == CutKeep::Both) {
    EXPECT_NEAR(mesh.area(), input.area(), 1e-4 * input.area());
  } else if (closed && options.keep == CutKeep::Both) {
    double total = 0.0;
    for (const auto& piece : r.pieces) {
      const EdgeCensus c = census(mesh, piece);
      EXPECT_EQ(c.boundary, 0u) << "a capped piece of closed input is closed";
      EXPECT_EQ(c.inconsistent, 0u) << "a capped piece is consistently oriented";
      total += volume_of(mesh, piece);
    }
    EXPECT_NEAR(total, input.volume(), 1e-4 * std::abs(input.volume()));
  }
  if (options.keep == CutKeep::Both) {
    EXPECT_GE(r.pieces.size(), 2u);
  }
}

// Expects every live face of `mesh` to have positive area (in double, from its float positions)
// and returns how many of them `counted` takes.
template <typename Counted>
std::size_t count_faces_of_positive_area(const SurfaceMesh& mesh, Counted counted) {
  std::size_t n = 0;
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    const glm::dvec3 u(mesh.position(t[0])), v(mesh.position(t[1])), w(mesh.position(t[2]));
    EXPECT_GT(glm::length(glm::cross(v - u, w - u)), 0.0) << "face " << f.index << " has zero area";
    n += counted(t);
  });
  return n;
}

// Cuts `mesh` by `plane` (expecting success) with an adjacency following the cut's log, checks
// the adjacency against a rebuild and the mesh's validity, and returns the adjacency.
Adjacency cut_with_checks(SurfaceMesh& mesh, const Plane& plane) {
  Adjacency adj = Adjacency::build(mesh);
  const CutResult r = cut_mesh(mesh, mesh.positions(), plane);
  test::follow_checked(adj, mesh, r.status, r.log);
  return adj;
}

}  // namespace

TEST(CutTest, plane_through_grid_vertices_and_along_edges) {
  const SurfaceMesh grid = test::make_grid(4, 4);
  // x = 0.5 runs through a column of vertices and along vertical edges; y = x along diagonals.
  for (const Plane& plane : {Plane{{0.5f, 0, 0}, {1, 0, 0}}, Plane{{0, 0.5f, 0}, {0, 1, 0}}, Plane{{0, 0, 0}, {1, -1, 0}},
                             Plane{{0.3f, 0, 0}, {1, 0.2f, 0}}}) {
    SCOPED_TRACE(plane.normal.x + 10 * plane.normal.y);
    check_cut(grid, plane, {}, 2);
  }
  SurfaceMesh mesh = grid;
  const CutResult r = cut_mesh(mesh, mesh.positions(), Plane{{0.5f, 0, 0}, {1, 0, 0}});
  EXPECT_EQ(r.intersection_points, 0u);     // no edge crosses: the plane runs through vertices
  EXPECT_EQ(r.rim_vertices.size(), 10u);    // five on the plane, each split into two sides
  ASSERT_EQ(r.pieces.size(), 2u);
  EXPECT_EQ(Adjacency::build(mesh).component_count(), 2u);
}

TEST(CutTest, crossing_edges_are_split_once_and_shared) {
  SurfaceMesh mesh = test::make_grid(3, 3);
  const CutResult r = cut_mesh(mesh, mesh.positions(), Plane{{0.5f, 0, 0}, {1, 0.1f, 0}});
  ASSERT_EQ(r.status, OpStatus::Ok);
  // Each crossed edge gave one new vertex; after separating the sides it has two copies.
  std::size_t added = 0, split = 0;
  for (const auto& e : r.log.edits) {
    added += std::holds_alternative<VertexAdded>(e);
    split += std::holds_alternative<VertexSplit>(e);
  }
  EXPECT_EQ(added, r.intersection_points);
  EXPECT_EQ(split, r.intersection_points);
  EXPECT_EQ(r.rim_vertices.size(), 2 * r.intersection_points);
}

TEST(CutTest, tangent_missing_and_zero_normal_planes) {
  const SurfaceMesh tube = test::make_tube(16, 4);
  for (const Plane& plane : {Plane{{1.0f, 0, 0}, {1, 0, 0}}, Plane{{0, 100, 0}, {0, 1, 0}}}) {
    SurfaceMesh mesh = tube;
    const CutResult r = cut_mesh(mesh, mesh.positions(), plane);
    EXPECT_EQ(r.status, OpStatus::NoIntersection);
    EXPECT_TRUE(r.log.empty());
    EXPECT_EQ(mesh.faces(), tube.faces());
  }
  SurfaceMesh mesh = tube;
  EXPECT_THROW(cut_mesh(mesh, mesh.positions(), Plane{{0, 0, 0}, {0, 0, 0}}), Error);
  EXPECT_THROW(cut_mesh(mesh, mesh.positions(), Plane{{0, NAN, 0}, {0, 1, 0}}), Error);
  EXPECT_THROW(cut_mesh(mesh, std::vector<glm::vec3>(3), Plane{{0, 1, 0}, {0, 1, 0}}), Error);
}

TEST(CutTest, capped_tube_gives_two_closed_pieces_with_cut_surface_faces) {
  const SurfaceMesh tube = test::make_tube(24, 6, 1.0f, 2.0f);
  CutOptions options;
  options.cap = true;
  check_cut(tube, Plane{{0, 0.9f, 0}, {0.2f, 1, 0.1f}}, options, 0);
  SurfaceMesh mesh = tube;
  const CutResult r = cut_mesh(mesh, mesh.positions(), Plane{{0, 0.9f, 0}, {0, 1, 0}}, options);
  const auto& flag = mesh.face_attrs().get<std::uint8_t>(attr::kCutSurface);
  std::size_t caps = 0;
  mesh.for_each_face([&](FaceId f, const Triangle&) { caps += flag[f.index]; });
  // The plane crosses each of the 24 side quads twice (an edge and the diagonal): a 48-gon per side.
  EXPECT_EQ(caps, 2u * (48 - 2));
  EXPECT_EQ(r.pieces.size(), 2u);
}

TEST(CutTest, cap_handles_nested_loops) {
  // A thick-walled pipe (outer and inner tube, inner reversed): the cross-section is an annulus.
  SurfaceMesh pipe = test::make_tube(32, 4, 2.0f, 2.0f);
  const SurfaceMesh inner = test::make_tube(32, 4, 1.0f, 2.0f);
  {
    // Append the inner tube reversed, and drop both tubes' end caps joined by an annulus: simpler,
    // keep both tubes closed; the section then has two nested loops per side.
    const auto offset = static_cast<std::uint32_t>(pipe.vertex_count());
    for (const auto& p : inner.positions()) pipe.add_vertex(p);
    inner.for_each_face([&](FaceId, const Triangle& t) {
      pipe.add_face(VertexId(t[0].index + offset), VertexId(t[2].index + offset), VertexId(t[1].index + offset));
    });
  }
  CutOptions options;
  options.cap = true;
  SurfaceMesh mesh = pipe;
  const double v0 = pipe.volume();
  const CutResult r = cut_mesh(mesh, mesh.positions(), Plane{{0, 1.1f, 0}, {0, 1, 0}}, options);
  ASSERT_EQ(r.pieces.size(), 2u);
  for (const auto& piece : r.pieces) {
    const EdgeCensus c = census(mesh, piece);
    EXPECT_EQ(c.boundary, 0u);
    EXPECT_EQ(c.inconsistent, 0u);
  }
  EXPECT_NEAR(mesh.volume(), v0, 1e-4 * std::abs(v0));
  // The cap is an annulus: its area is the ring between the two 32-gons.
  const double ring = 0.5 * 32 * std::sin(2 * M_PI / 32) * (4.0 - 1.0);
  const auto& flag = mesh.face_attrs().get<std::uint8_t>(attr::kCutSurface);
  double cap_area = 0.0;
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    if (!flag[f.index]) return;
    cap_area += 0.5 * glm::length(glm::cross(mesh.position(t[1]) - mesh.position(t[0]), mesh.position(t[2]) - mesh.position(t[0])));
  });
  EXPECT_NEAR(cap_area, 2 * ring, 1e-3 * ring);
}

TEST(CutTest, keep_one_side_and_split_components) {
  SurfaceMesh mesh = test::make_grid(6, 2);
  CutOptions options;
  options.keep = CutKeep::Negative;
  const CutResult r = cut_mesh(mesh, mesh.positions(), Plane{{0.45f, 0, 0}, {1, 0, 0}}, options);
  ASSERT_EQ(r.pieces.size(), 1u);
  EXPECT_EQ(r.piece_sides[0], -1);
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (auto v : t) EXPECT_LE(mesh.position(v).x, 0.45f + 1e-5f);
  });
  // Two separate tubes side by side, cut across both, with components: four pieces.
  SurfaceMesh two = test::make_tube(12, 3);
  const SurfaceMesh other = test::make_tube(12, 3);
  const auto offset = static_cast<std::uint32_t>(two.vertex_count());
  for (const auto& p : other.positions()) two.add_vertex(p + glm::vec3(5, 0, 0));
  other.for_each_face([&](FaceId, const Triangle& t) {
    two.add_face(VertexId(t[0].index + offset), VertexId(t[1].index + offset), VertexId(t[2].index + offset));
  });
  CutOptions comps;
  comps.split_components = true;
  const CutResult rc = cut_mesh(two, two.positions(), Plane{{0, 1, 0}, {0, 1, 0}}, comps);
  EXPECT_EQ(rc.pieces.size(), 4u);
}

TEST(CutTest, non_manifold_input_is_cut) {
  SurfaceMesh mesh = test::make_grid(2, 2);
  {  // a fin on the middle vertical edge makes it non-manifold
    MeshEditor editor(mesh);
    const VertexId tip = mesh.add_vertex({0.5f, 0.25f, 1.0f});
    mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0)[tip.index] = {1, 0, 0, 0};
    mesh.add_face(VertexId(1), VertexId(4), tip);
  }
  ASSERT_EQ(Adjacency::build(mesh).nonmanifold_edges().size(), 1u);
  check_cut(mesh, Plane{{0, 0.3f, 0}, {0, 1, 0.05f}}, {}, 0);
}

TEST(CutTest, random_planes_on_every_asset_keep_all_invariants) {
  const unsigned seed = 20261121;
  for (const auto& path : test::asset_models()) {
    SCOPED_TRACE(path + " (seed " + std::to_string(seed) + ")");
    const Model model = read_gltf(path);
    const std::size_t joints = model.skins.empty() ? 0 : model.skins[0].joints.size();
    std::mt19937 rng(seed);
    for (int i = 0; i < 200; ++i) {
      for (const auto& mesh : model.meshes)
        for (const auto& prim : mesh.primitives) {
          const Plane plane = random_plane(prim.mesh.bounds(), rng);
          CutOptions options;
          options.cap = i % 2 == 1;
          options.keep = i % 7 == 3 ? CutKeep::Positive : CutKeep::Both;
          SCOPED_TRACE("plane " + std::to_string(i));
          check_cut(prim.mesh, plane, options, joints);
          if (::testing::Test::HasFatalFailure()) return;
        }
    }
  }
}

TEST(CutTest, posed_cut_puts_rim_vertices_on_the_plane_in_that_pose) {
  const Model model = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  int node = -1;
  for (std::size_t n = 0; n < model.nodes.size(); ++n)
    if (model.nodes[n].mesh == 0) node = static_cast<int>(n);
  const float t = 0.3f * model.animations[0].duration();
  const auto world = world_matrices(model, sample_pose(model, 0, t));
  SurfaceMesh mesh = model.meshes[0].primitives[0].mesh;
  const auto posed = posed_positions(model, node, mesh, world);
  const float size = world_bounds(model, sample_pose(model, 0, t)).diagonal();
  const Plane plane{{0.3f, 6.0f, 0.0f}, {0.3f, 1.0f, 0.2f}};
  const CutResult r = cut_mesh(mesh, posed, plane);
  ASSERT_EQ(r.status, OpStatus::Ok);
  const auto after = posed_positions(model, node, mesh, world);  // re-skinned, new vertices included
  ASSERT_FALSE(r.rim_vertices.empty());
  for (VertexId v : r.rim_vertices) ASSERT_LE(std::abs(signed_distance(after[v.index], plane)), 1e-3 * size);
  // The same plane in the bind pose would land elsewhere: the pose matters.
  double bind_offset = 0.0;
  for (VertexId v : r.rim_vertices) bind_offset = std::max(bind_offset, std::abs(signed_distance(mesh.position(v), plane)));
  EXPECT_GT(bind_offset, 1e-3 * size);
}

TEST(CutTest, a_posed_cut_moves_each_new_vertex_after_adding_it) {
  // Cut through a PosedMesh, as cut_model does: each crossing placed in the pose is moved after
  // its VertexAdded (edit_log.h), not necessarily right after it.
  const Model model = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  int node = -1;
  for (std::size_t n = 0; n < model.nodes.size(); ++n)
    if (model.nodes[n].mesh == 0) node = static_cast<int>(n);
  ASSERT_GE(node, 0);
  const auto world = world_matrices(model, sample_pose(model, 0, 0.3f * model.animations[0].duration()));
  SurfaceMesh mesh = model.meshes[0].primitives[0].mesh;
  PosedMesh posed;
  posed.posed = posed_positions(model, node, mesh, world);
  for (const glm::vec3& p : posed.posed) posed.bounds.add(p);
  const int skin = model.nodes[static_cast<std::size_t>(node)].skin;
  if (skin >= 0) posed.joints = joint_matrices(model, skin, world);
  posed.world = world[static_cast<std::size_t>(node)];
  posed.gridless = true;
  const std::size_t first_new = mesh.vertex_count();
  const CutResult r = cut_mesh(mesh, posed, Plane{{0.3f, 6.0f, 0.0f}, {0.3f, 1.0f, 0.2f}});
  ASSERT_EQ(r.status, OpStatus::Ok);
  std::vector<bool> added(mesh.vertex_count(), false);
  std::size_t new_moved = 0;
  for (const Edit& e : r.log.edits) {
    if (const auto* a = std::get_if<VertexAdded>(&e)) added[a->v.index] = true;
    const auto* m = std::get_if<VertexMoved>(&e);
    if (m == nullptr || m->v.index < first_new) continue;
    ++new_moved;
    EXPECT_TRUE(added[m->v.index]) << "vertex " << m->v.index << " moved before it was added";
  }
  EXPECT_GT(new_moved, 0u);
}

TEST(CutTest, model_cut_exports_animated_pieces_that_pass_the_validator) {
  const std::string dir = test::temp_dir("cutmodel");
  std::vector<std::string> outputs;
  std::mt19937 rng(5);
  for (const auto& path : test::asset_models()) {
    SCOPED_TRACE(path);
    const Model original = read_gltf(path);
    const BoundingBox box = world_bounds(original, rest_pose(original));
    for (int i = 0; i < 12; ++i) {
      Model model = original;
      CutOptions options;
      options.cap = i % 2 == 0;
      options.split_components = i % 3 == 0;
      const ModelCutResult r = cut_model(model, random_plane(box, rng), options);
      if (r.status == OpStatus::NoIntersection) continue;
      EXPECT_GE(r.piece_nodes.size(), 2u);
      for (int n : r.piece_nodes) {
        EXPECT_EQ(model.nodes[n].skin, original.nodes[r.piece_nodes[0]].skin) << "pieces stay bound to the skin";
        const auto& m = model.meshes[model.nodes[n].mesh];
        for (const auto& p : m.primitives) test::expect_valid(p.mesh);
      }
      const std::string out = dir + "/" + std::filesystem::path(path).stem().string() + std::to_string(i) + (i % 2 ? ".gltf" : ".glb");
      write_gltf(model, out);
      outputs.push_back(out);
      const Model again = read_gltf(out);
      EXPECT_EQ(again.skins.size(), original.skins.size());
      EXPECT_EQ(again.animations.size(), original.animations.size());
    }
  }
  ASSERT_FALSE(outputs.empty());
  std::string files;
  for (const auto& o : outputs) files += " " + test::quote(o);
  const auto v = test::run_command("node " + test::quote(DEEPCUT_VALIDATOR_SCRIPT) + files);
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
  std::filesystem::remove_all(dir);
}

}  // namespace deepcut

namespace deepcut {

TEST(CutTest, posed_recut_with_the_same_plane_finds_nothing_and_piece_names_stay_unique) {
  Model model = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  const Plane plane{{0.0f, 8.0f, 0.0f}, {0.3f, 1.0f, 0.0f}};
  const float t = 2.0f;
  ASSERT_EQ(cut_model(model, plane, {}, 0, t).status, OpStatus::Ok);
  // The rim was snapped onto the plane in that pose, so nothing is left to cut.
  Model again = model;
  EXPECT_EQ(cut_model(again, plane, {}, 0, t).status, OpStatus::NoIntersection);
  // A second, different cut makes more pieces; no two nodes share a name.
  ASSERT_EQ(cut_model(model, Plane{{0, 5, 0}, {0, 1, 0.2f}}, {}, 0, t).status, OpStatus::Ok);
  std::set<std::string> names;
  for (const auto& n : model.nodes)
    if (n.mesh >= 0) {
      EXPECT_TRUE(names.insert(n.name).second) << "duplicate node name " << n.name;
    }
}

// Found by the random sequences (RiggedSimple seed 20261809 step 84): a face lying in the cut
// plane whose neighbours all fall on the other side becomes a piece of its own, its edges are rim
// edges, and the cap used to cover that rim with the same three vertices again (reversed): a
// duplicate face.
TEST(CutTest, cap_never_duplicates_a_face_lying_in_the_plane) {
  SurfaceMesh mesh;
  // A tetrahedron standing below z = 0 with its top face in the plane, and one wholly above.
  const VertexId a = mesh.add_vertex({0, 0, 0}), b = mesh.add_vertex({1, 0, 0}), c = mesh.add_vertex({0, 1, 0}),
                 d = mesh.add_vertex({0.3f, 0.3f, -1});
  mesh.add_face(a, b, c);
  mesh.add_face(a, d, b);
  mesh.add_face(b, d, c);
  mesh.add_face(c, d, a);
  const VertexId e = mesh.add_vertex({3, 0, 1}), f = mesh.add_vertex({4, 0, 1}), g = mesh.add_vertex({3, 1, 1}),
                 h = mesh.add_vertex({3.3f, 0.3f, 2});
  mesh.add_face(e, g, f);
  mesh.add_face(e, f, h);
  mesh.add_face(f, g, h);
  mesh.add_face(g, e, h);
  CutOptions options;
  options.cap = true;
  const CutResult r = cut_mesh(mesh, mesh.positions(), Plane{{0, 0, 0}, {0, 0, 1}}, options);
  ASSERT_EQ(r.status, OpStatus::Ok);
  std::set<std::array<std::uint32_t, 3>> seen;
  mesh.for_each_face([&](FaceId face, const Triangle& t) {
    std::array<std::uint32_t, 3> k{t[0].index, t[1].index, t[2].index};
    std::sort(k.begin(), k.end());
    EXPECT_TRUE(seen.insert(k).second) << "face " << face.index << " repeats the vertices of another face";
  });
  test::expect_valid(mesh);
  EXPECT_TRUE(Adjacency::build(mesh).nonmanifold_edges().empty());
}

}  // namespace deepcut

namespace deepcut {

// Found by the random sequences (pinched vertices after cuts): a plane through a saddle vertex
// (its ring goes up, down, up, down) leaves each side two wedges meeting only at that vertex.
// Each wedge gets its own vertex, so both sides stay manifold.
TEST(CutTest, plane_through_a_saddle_vertex_leaves_no_pinched_vertex) {
  for (const CutKeep keep : {CutKeep::Both, CutKeep::Positive, CutKeep::Negative}) {
    SurfaceMesh mesh;
    const VertexId v = mesh.add_vertex({0, 0, 0});
    const VertexId ring[4] = {mesh.add_vertex({1, 0, 1}), mesh.add_vertex({0, 1, -1}), mesh.add_vertex({-1, 0, 1}),
                              mesh.add_vertex({0, -1, -1})};
    for (int k = 0; k < 4; ++k) mesh.add_face(v, ring[k], ring[(k + 1) % 4]);
    ASSERT_TRUE(test::pinched_vertices(mesh).empty());
    Adjacency adj = Adjacency::build(mesh);
    CutOptions options;
    options.keep = keep;
    const CutResult r = cut_mesh(mesh, mesh.positions(), Plane{{0, 0, 0}, {0, 0, 1}}, options);
    ASSERT_EQ(r.status, OpStatus::Ok);
    EXPECT_TRUE(test::pinched_vertices(mesh).empty()) << "keep " << int(keep);
    adj.apply(r.log);
    test::expect_adjacency_matches_rebuild(adj, mesh);
    test::expect_valid(mesh);
    // Four wedges with both sides kept, two with one (each the two half-faces around one ring
    // vertex), and a centre vertex each.
    std::size_t centre_copies = 0;
    for (std::uint32_t i = 0; i < mesh.vertex_count(); ++i)
      centre_copies += mesh.position(VertexId(i)) == glm::vec3(0.0f) && !adj.vertex_faces(VertexId(i)).empty();
    EXPECT_EQ(centre_copies, keep == CutKeep::Both ? 4u : 2u) << "keep " << int(keep);
  }
}

// Found by the random sequences (zero-area faces after cuts): a needle whose lone corner X is on
// one side and whose two far corners lie one float step apart on the other. Both crossings round
// to one bind position; they become one vertex, and the needle's tip beyond the plane (a face
// with two corners at one point) is not made.
TEST(CutTest, a_needle_split_near_its_tip_makes_no_zero_area_face) {
  SurfaceMesh mesh = test::make_needle_fan();
  const Adjacency adj = cut_with_checks(mesh, Plane{{0.5f, 0, 0}, {1, 0, 0}});
  const std::size_t near_side = count_faces_of_positive_area(mesh, [&](const Triangle& t) {
    return std::max({mesh.position(t[0]).x, mesh.position(t[1]).x, mesh.position(t[2]).x}) <= 0.5f;
  });
  EXPECT_EQ(near_side, 2u) << "X keeps two faces, not the needle's zero-area tip";
  EXPECT_TRUE(adj.nonmanifold_edges().empty());
  EXPECT_NEAR(mesh.area(), 0.5, 1e-5) << "the cut keeps the area (two flanking faces of 0.25, the needle's none)";
}

// A sliver whose crossings round one float step apart (not to one position): the needle X a b,
// a and b one float step apart in x, is crossed by a tilted plane at 0.3 of its length. The
// crossings round to x = 1 like X, one float step apart in y: X and both crossings lie on one
// float line, so the tip triangle (X and the crossings) would have zero area. The crossings are
// a hair apart and become one vertex, as crossings at one position do.
TEST(CutTest, a_sliver_whose_crossings_round_one_step_apart_makes_no_zero_area_face) {
  SurfaceMesh mesh;
  const float one_up = std::nextafter(1.0f, 2.0f);
  const VertexId x = mesh.add_vertex({1, 0, 0}), p = mesh.add_vertex({0.5f, 1, 0}), a = mesh.add_vertex({1, 1, 0}),
                 b = mesh.add_vertex({one_up, 1, 0}), q = mesh.add_vertex({1.5f, 1, 0});
  mesh.add_face(x, p, a);
  mesh.add_face(x, a, b);
  mesh.add_face(x, b, q);
  const Adjacency adj = cut_with_checks(mesh, Plane{{1, 0.3f, 0}, {1, 1, 0}});
  const std::size_t near_side = count_faces_of_positive_area(
      mesh, [&](const Triangle& t) { return t[0] == x || t[1] == x || t[2] == x; });
  EXPECT_EQ(near_side, 2u) << "X keeps its two flanking faces' pieces, not the sliver's tip";
  EXPECT_TRUE(adj.nonmanifold_edges().empty());
}

TEST(CutTest, the_result_does_not_depend_on_the_thread_count) {
  // Large enough for several parallel chunks of vertices and faces. Three cuts per thread count:
  // whole, split into components, and with a vertex no face uses (found by the face scan).
  const SurfaceMesh input = test::make_grid(260, 140);
  SurfaceMesh with_stray = input;
  with_stray.add_vertex({9.0f, -7.0f, 2.0f});
  const Plane plane{{0.5f, 0.5f, 0.0f}, {1.0f, 0.37f, 0.0f}};
  const std::size_t saved = thread_count();
  std::vector<SurfaceMesh> meshes;
  std::vector<CutResult> results;
  for (std::size_t threads : {1u, 2u, 3u}) {
    set_thread_count(threads);
    for (int variant = 0; variant < 3; ++variant) {
      SurfaceMesh mesh = variant == 2 ? with_stray : input;
      CutOptions options;
      options.split_components = variant == 1;
      results.push_back(cut_mesh(mesh, mesh.positions(), plane, options));
      meshes.push_back(std::move(mesh));
    }
  }
  set_thread_count(saved);
  for (std::size_t i = 3; i < meshes.size(); ++i) {
    const std::size_t j = i % 3;  // same variant, one thread
    EXPECT_EQ(meshes[i].faces(), meshes[j].faces());
    EXPECT_EQ(meshes[i].positions(), meshes[j].positions());
    EXPECT_EQ(results[i].pieces, results[j].pieces);
    EXPECT_EQ(results[i].rim_vertices, results[j].rim_vertices);
    EXPECT_EQ(results[i].log.size(), results[j].log.size());
  }
  ASSERT_EQ(results[0].pieces.size(), 2u);
  EXPECT_EQ(results[0].pieces[0].size() + results[0].pieces[1].size(), meshes[0].face_count());
  ASSERT_EQ(results[2].status, OpStatus::Ok);
  EXPECT_EQ(results[2].pieces, results[0].pieces);  // the stray vertex changes nothing
}

TEST(CutTest, the_face_scan_splits_only_ranges_worth_a_thread) {
  // Below kMinPassGrain faces the scan is one chunk on the caller whatever the thread count (a
  // 25k-triangle cut pays more for the pool than it saves); above it, the threads share it.
  const std::size_t saved = thread_count();
  set_thread_count(2);
  for (const auto& [nx, ny] : {std::pair{100, 100}, std::pair{260, 140}}) {
    const SurfaceMesh mesh = test::make_grid(nx, ny);
    const std::vector<std::uint8_t> bits(mesh.vertex_count(), 1);  // every vertex on the positive side
    const std::vector<detail::ScannedFaces> parts = detail::scan_faces(mesh, bits.data(), nullptr);
    EXPECT_EQ(parts.size(), mesh.face_slots() < detail::kMinPassGrain ? 1u : 2u) << mesh.face_slots() << " faces";
    std::size_t clean = 0;
    for (const detail::ScannedFaces& part : parts) clean += part.clean[0].size();
    EXPECT_EQ(clean, mesh.face_slots());
  }
  set_thread_count(saved);
}

TEST(CutTest, vertex_sides_sixteen_at_a_time_follow_the_rule_of_each_vertex) {
  // Sides snap sixteen vertices at a time, then one by one: every lane where its vertex is (a
  // count that leaves a tail, every side in every lane). A negative tolerance leaves a band of
  // vertices both above and below (side 0, all bits set), as the one-by-one rule has it.
  SurfaceMesh mesh;
  for (int i = 0; i < 53; ++i) mesh.add_vertex(glm::vec3(float((i * 5) % 7 - 3), float(i % 3), 0.0f));
  for (std::uint32_t i = 0; i + 2 < 53; ++i) mesh.add_face(VertexId(i), VertexId(i + 1), VertexId(i + 2));
  const glm::vec3 origin(0.0f), normal(1.0f, 0.0f, 0.0f);
  for (const float tolerance : {1e-5f, -0.1f}) {
    const detail::VertexSides sides =
        detail::classify_vertices(mesh, mesh.positions(), origin, normal, tolerance, mesh.vertex_count(), nullptr);
    const float band = 0.1f * glm::length(glm::vec3(6.0f, 2.0f, 0.0f));  // |tolerance| of the diagonal
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
      const float d = mesh.position(VertexId(v)).x;
      const bool above = tolerance > 0.0f ? d > 0.0f : d > -band;
      const bool below = tolerance > 0.0f ? d < 0.0f : d < band;
      const int sign = int(above) - int(below);
      const unsigned bits = (above ? 1u : 0u) | (below ? 2u : 0u) | (above || below ? 0u : 4u);
      EXPECT_EQ(sides.dist[v], d) << v;
      EXPECT_EQ(sides.sign[v], sign) << "vertex " << v << ", tolerance " << tolerance;
      EXPECT_EQ(sides.bits[v], above && below ? 0xffu : bits) << "vertex " << v << ", tolerance " << tolerance;
    }
    EXPECT_TRUE(sides.both_sides);
  }
}

TEST(CutTest, a_capped_cut_does_not_depend_on_the_thread_count) {
  // The caps' polygons are triangulated on the pool when they are big enough (2048 corners in
  // all): this plane cuts the cactus's trunk and two arms, three loops on each side.
  CactusOptions cactus;
  cactus.target_triangles = 400000;
  const SurfaceMesh input = std::move(make_cactus(cactus).meshes[0].primitives[0].mesh);
  const BoundingBox box = input.bounds();
  const Plane plane{0.5f * (box.min + box.max) + glm::vec3(0.0f, 0.13f, 0.0f), glm::vec3(0.1f, 1.0f, 0.05f)};
  const std::size_t saved = thread_count();
  std::vector<SurfaceMesh> meshes;
  std::vector<CutResult> results;
  for (std::size_t threads : {1u, 2u, 3u}) {
    set_thread_count(threads);
    for (bool split : {false, true}) {
      SurfaceMesh mesh = input;
      CutOptions options;
      options.cap = true;
      options.split_components = split;
      results.push_back(cut_mesh(mesh, mesh.positions(), plane, options));
      meshes.push_back(std::move(mesh));
    }
  }
  set_thread_count(saved);
  const auto* flags = meshes[0].face_attrs().find<std::uint8_t>(attr::kCutSurface);
  ASSERT_NE(flags, nullptr);
  EXPECT_GT(std::count(flags->data().begin(), flags->data().end(), std::uint8_t(1)), 2048);
  for (std::size_t i = 2; i < meshes.size(); ++i) {
    const std::size_t j = i % 2;  // same options, one thread
    EXPECT_EQ(meshes[i].faces(), meshes[j].faces());
    EXPECT_EQ(meshes[i].corner_attrs().find<glm::vec2>(attr::kUv0)->data(),
              meshes[j].corner_attrs().find<glm::vec2>(attr::kUv0)->data());
    EXPECT_EQ(meshes[i].corner_attrs().find<glm::vec3>(attr::kNormal)->data(),
              meshes[j].corner_attrs().find<glm::vec3>(attr::kNormal)->data());
    EXPECT_EQ(results[i].pieces, results[j].pieces);
    EXPECT_EQ(results[i].rim_vertices, results[j].rim_vertices);
    EXPECT_EQ(results[i].log.size(), results[j].log.size());
  }
}

// A vertex no face uses counts for neither side. Far off, it would widen the tolerance (the
// model size) until the plane took in the whole grid; on the other side of the plane, it would
// make a grid lying on one side look crossed.
TEST(CutTest, a_vertex_no_face_uses_changes_nothing) {
  const SurfaceMesh grid = test::make_grid(8, 8);
  const auto n = static_cast<std::uint32_t>(grid.vertex_count());
  // The cut of the grid with the stray vertex n, its ids shifted past n, is the grid's cut.
  auto shifted = [n](VertexId v) { return v.index < n ? v : VertexId(v.index + 1); };
  // Far off, the stray vertex's tolerance puts the whole grid on the plane: one side found
  // first, then both once the scan finds the vertex unused. About 10 units off, both sides are
  // found first with a wider tolerance: the classification and the face scan are redone.
  for (const glm::vec3& off : {glm::vec3(1e5f, -1e5f, 3e4f), glm::vec3(9.0f, -7.0f, 2.0f)})
    for (bool split : {false, true}) {
      SCOPED_TRACE(std::to_string(off.x) + (split ? " split" : ""));
      CutOptions options;
      options.split_components = split;
      const Plane plane{{0.53f, 0.5f, 0.0f}, {1.0f, 0.21f, 0.0f}};
      SurfaceMesh plain = grid, stray = grid;
      stray.add_vertex(off);
      const CutResult a = cut_mesh(plain, plain.positions(), plane, options);
      const CutResult b = cut_mesh(stray, stray.positions(), plane, options);
      ASSERT_EQ(a.status, OpStatus::Ok);
      ASSERT_EQ(b.status, OpStatus::Ok);
      ASSERT_EQ(plain.face_slots(), stray.face_slots());
      for (std::size_t f = 0; f < plain.face_slots(); ++f) {
        const Triangle& t = plain.faces()[f];
        EXPECT_EQ((Triangle{shifted(t[0]), shifted(t[1]), shifted(t[2])}), stray.faces()[f]);
        EXPECT_EQ(plain.is_deleted(FaceId(std::uint32_t(f))), stray.is_deleted(FaceId(std::uint32_t(f))));
      }
      EXPECT_EQ(a.pieces, b.pieces);
      ASSERT_EQ(a.rim_vertices.size(), b.rim_vertices.size());
      for (std::size_t i = 0; i < a.rim_vertices.size(); ++i)
        EXPECT_EQ(shifted(a.rim_vertices[i]), b.rim_vertices[i]);
    }
  // The grid (z = 0) wholly behind the plane z = 0.5, the stray vertex in front of it.
  SurfaceMesh stray = grid;
  stray.add_vertex({0.5f, 0.5f, 2.0f});
  EXPECT_EQ(cut_mesh(stray, stray.positions(), Plane{{0, 0, 0.5f}, {0, 0, 1}}).status,
            OpStatus::NoIntersection);
  EXPECT_EQ(stray.face_slots(), grid.face_slots());
}

namespace {

// Open cones standing on the plane z = 0 (apex up), as one piece: a cone of each (radius, centre
// x) in `cones` (a negative radius: the cone turned inside out, its ring running the other way).
// Ring vertices at one point are one vertex.
struct OpenCones {
  SurfaceMesh mesh;
  std::vector<std::int8_t> sign;
  std::vector<std::vector<VertexId>> rings;
};
OpenCones open_cones(const std::vector<std::pair<float, float>>& cones, int around) {
  OpenCones c;
  std::map<std::pair<float, float>, VertexId> at;
  for (const auto& [r, x] : cones) {
    const VertexId apex = c.mesh.add_vertex({x, 0, 1});
    c.sign.push_back(1);
    std::vector<VertexId> ring;
    for (int i = 0; i < around; ++i) {
      const double a = 2 * M_PI * i / around;
      const double sin_a = std::abs(std::sin(a)) < 1e-9 ? 0.0 : std::sin(a);  // on the axis at a half turn
      const glm::vec3 p(x + std::abs(r) * std::cos(a), std::abs(r) * sin_a, 0);
      const auto [it, added] = at.emplace(std::pair(p.x, p.y), VertexId());
      if (added) {
        it->second = c.mesh.add_vertex(p);
        c.sign.push_back(0);
      }
      ring.push_back(it->second);
    }
    for (int i = 0; i < around; ++i) {
      const VertexId a = ring[i], b = ring[(i + 1) % around];
      r > 0 ? c.mesh.add_face(apex, a, b) : c.mesh.add_face(apex, b, a);
    }
    c.rings.push_back(ring);
  }
  return c;
}

}  // namespace

// make_caps says its caps are whole fans (the cut then skips looking at their vertices' fans)
// for a loop without holes, where every cap face at a rim vertex is in one fan from one of the
// vertex's rim edges to the other; not for an annulus, whose hole is bridged in. Two cones whose
// rims touch at a vertex (two rim steps leave it: the loops are traced the general way) are
// capped closed too, each loop by itself.
TEST(CutTest, caps_are_whole_fans_only_without_holes) {
  using Cones = std::vector<std::pair<float, float>>;
  for (const Cones& cones : {Cones{{2.0f, 0.0f}}, Cones{{2.0f, 0.0f}, {2.0f, 4.0f}}, Cones{{2.0f, 0.0f}, {-1.0f, 0.0f}}}) {
    const bool annulus = cones.back().first < 0;
    OpenCones c = open_cones(cones, 12);
    ASSERT_EQ(c.sign.size(), cones.size() * 13 - (cones.size() == 2 && !annulus ? 1 : 0));  // touching: one shared
    const detail::PosedOverlay<glm::vec3> posed(c.mesh.positions());
    std::vector<detail::CapInput> in(1);
    in[0].normal = {0, 0, 1};
    in[0].posed = &posed;
    in[0].sign = &c.sign;
    std::vector<std::vector<FaceId>> pieces(1);
    c.mesh.for_each_face([&](FaceId f, const Triangle&) {
      in[0].rim_faces.push_back(f);
      pieces[0].push_back(f);
    });
    const auto first_cap = static_cast<std::uint32_t>(c.mesh.face_slots());
    MeshEditor editor(c.mesh);
    EXPECT_EQ(detail::make_caps(editor, in, pieces), !annulus);
    const EdgeCensus census_of_piece = census(c.mesh, pieces[0]);
    EXPECT_EQ(census_of_piece.boundary, 0u);
    EXPECT_EQ(census_of_piece.inconsistent, 0u);
    EXPECT_EQ(c.mesh.face_slots() - first_cap, annulus ? 24u : cones.size() * 10u);
    if (cones.size() > 1) continue;
    const auto& ring = c.rings[0];
    for (std::size_t i = 0; i < ring.size(); ++i) {
      // The cap faces at ring[i], walked from the one on the rim edge to ring[i - 1] across
      // shared edges, end on the rim edge to ring[i + 1] having met every one of them.
      std::vector<Triangle> fan;
      for (auto f = first_cap; f < c.mesh.face_slots(); ++f) {
        const Triangle& t = c.mesh.face(FaceId(f));
        if (std::count(t.begin(), t.end(), ring[i])) fan.push_back(t);
      }
      VertexId at = ring[(i + ring.size() - 1) % ring.size()];
      std::size_t walked = 0;
      for (bool stepped = true; stepped;) {
        stepped = false;
        for (Triangle& t : fan)
          if (t[0] != t[1] && std::count(t.begin(), t.end(), at)) {
            VertexId next = at;
            for (const VertexId v : t)
              if (v != ring[i] && v != at) next = v;
            at = next;
            t[1] = t[0];  // walked
            ++walked;
            stepped = true;
            break;
          }
      }
      EXPECT_EQ(walked, fan.size()) << "vertex " << i;
      EXPECT_EQ(at, ring[(i + 1) % ring.size()]) << "vertex " << i;
    }
  }
}

}  // namespace deepcut
