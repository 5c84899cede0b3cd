// SPDX-License-Identifier: MIT
// Morph targets in the pose: weights from the node, the mesh, the clip (step, linear, cubic
// spline) and the designer's hand; morphs applied before skinning wherever a pose is computed,
// checked against skinning written out here; and cut, tear and drill made at a pose with non-zero
// weights: new vertices on the posed input surface, rims on the plane or cylinder, caps and walls
// attached to their rims whatever the morph plays, every piece with its targets and channels.
#include "deepcut/core/morph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/ops/drill.h"
#include "deepcut/core/ops/tear.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/skinning.h"
#include "fixtures.h"
#include "posed_checks.h"
#include "tools.h"

namespace deepcut {
namespace {

constexpr int kTube = 0;  // the morph tube's mesh node

// Posing written out independently of the library: bind + sum w_i delta_i, then the weighted sum
// of the joint matrices (world(joint) x inverse bind), or the node's world matrix without a skin.
std::vector<glm::vec3> pose_by_hand(const Model& model, int node, const SurfaceMesh& mesh, const Pose& pose) {
  const std::vector<glm::mat4> world = world_matrices(model, pose);
  const Node& n = model.nodes[static_cast<std::size_t>(node)];
  const std::vector<float>& w = pose.weights[static_cast<std::size_t>(node)];
  const auto* joints = mesh.vertex_attrs().find<glm::u16vec4>(attr::kJoints0);
  const auto* influence = mesh.vertex_attrs().find<glm::vec4>(attr::kWeights0);
  std::vector<glm::vec3> out(mesh.vertex_count());
  for (std::size_t v = 0; v < out.size(); ++v) {
    glm::dvec3 bind(mesh.positions()[v]);
    for (std::size_t i = 0; i < w.size(); ++i)
      bind += double(w[i]) * glm::dvec3(mesh.vertex_attrs().get<glm::vec3>(attr::morph_position_name(int(i)))[v]);
    glm::dmat4 m(0.0);
    if (n.skin >= 0 && joints && influence) {
      const Skin& skin = model.skins[static_cast<std::size_t>(n.skin)];
      for (int k = 0; k < 4; ++k) {
        const int j = (*joints)[v][k];
        if ((*influence)[v][k] == 0.0f) continue;
        m += double((*influence)[v][k]) *
             glm::dmat4(world[static_cast<std::size_t>(skin.joints[static_cast<std::size_t>(j)])] *
                        skin.inverse_bind_matrices[static_cast<std::size_t>(j)]);
      }
    } else {
      m = glm::dmat4(world[static_cast<std::size_t>(node)]);
    }
    out[v] = glm::vec3(m * glm::dvec4(bind, 1.0));
  }
  return out;
}

double point_segment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

// Distance from `p` to the triangle abc.
double point_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double len = glm::length(n);
  if (len > 0.0) {
    const glm::dvec3 u = n / len;
    const glm::dvec3 q = p - glm::dot(p - a, u) * u;
    const bool inside = glm::dot(glm::cross(b - a, q - a), n) >= 0.0 && glm::dot(glm::cross(c - b, q - b), n) >= 0.0 &&
                        glm::dot(glm::cross(a - c, q - c), n) >= 0.0;
    if (inside) return std::abs(glm::dot(p - a, u));
  }
  return std::min({point_segment(p, a, b), point_segment(p, b, c), point_segment(p, c, a)});
}

// The posed triangles of every instance of `model` at `key`, posed by hand.
struct PosedSurface {
  std::vector<std::array<glm::dvec3, 3>> tris;
  double size = 0.0;
  double distance(const glm::vec3& p) const {
    double best = 1e300;
    for (const auto& t : tris) best = std::min(best, point_triangle(glm::dvec3(p), t[0], t[1], t[2]));
    return best;
  }
};

PosedSurface posed_surface(const Model& model, const PoseKey& key) {
  const Pose pose = sample_pose(model, key);
  PosedSurface out;
  BoundingBox box;
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    if (model.nodes[n].mesh < 0) continue;
    for (const Primitive& prim : model.meshes[static_cast<std::size_t>(model.nodes[n].mesh)].primitives) {
      const auto posed = pose_by_hand(model, static_cast<int>(n), prim.mesh, pose);
      prim.mesh.for_each_face([&](FaceId, const Triangle& t) {
        out.tris.push_back({glm::dvec3(posed[t[0].index]), glm::dvec3(posed[t[1].index]), glm::dvec3(posed[t[2].index])});
        for (VertexId v : t) box.add(posed[v.index]);
      });
    }
  }
  out.size = box.diagonal();
  return out;
}

// Vertices used by a live face of `mesh`.
std::vector<std::uint32_t> used_vertices(const SurfaceMesh& mesh) {
  std::vector<char> used(mesh.vertex_count(), 0);
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (VertexId v : t) used[v.index] = 1;
  });
  std::vector<std::uint32_t> out;
  for (std::uint32_t v = 0; v < used.size(); ++v)
    if (used[v]) out.push_back(v);
  return out;
}

// Vertices on an edge only one live face of `mesh` uses (the rims of holes).
std::vector<char> on_boundary(const SurfaceMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (int k = 0; k < 3; ++k)
      ++uses[std::minmax(t[k].index, t[(k + 1) % 3].index)];
  });
  std::vector<char> out(mesh.vertex_count(), 0);
  for (const auto& [edge, count] : uses)
    if (count == 1) out[edge.first] = out[edge.second] = 1;
  return out;
}

// True when every live corner of `mesh` has a zero NORMAL delta for target 0 (caps and walls keep
// their own normals whatever the weights).
bool zero_normal_deltas(const SurfaceMesh& mesh) {
  const auto& dn = mesh.corner_attrs().get<glm::vec3>(attr::morph_normal_name(0));
  bool zero = true;
  mesh.for_each_face([&](FaceId f, const Triangle&) {
    for (int k = 0; k < 3; ++k) zero &= dn[SurfaceMesh::corner(f, k)] == glm::vec3(0.0f);
  });
  return zero;
}

// The largest distance, at pose `key`, from a vertex of `part` (a cap or wall primitive drawn by
// node `part_node`) to the nearest vertex of `body` (drawn by `body_node`) over the vertices of
// `part` that lie on `body`'s surface at the pose the operation was made in (`partners`: for each
// such vertex its partner in `body`).
double largest_gap(const Model& model, const PoseKey& key, int part_node, const SurfaceMesh& part, int body_node,
                   const SurfaceMesh& body, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& partners) {
  const Pose pose = sample_pose(model, key);
  const std::vector<glm::mat4> world = world_matrices(model, pose);
  const auto a = posed_positions(model, part_node, part, world, pose.weights[static_cast<std::size_t>(part_node)]);
  const auto b = posed_positions(model, body_node, body, world, pose.weights[static_cast<std::size_t>(body_node)]);
  double gap = 0.0;
  for (const auto& [x, y] : partners) gap = std::max(gap, double(glm::length(a[x] - b[y])));
  return gap;
}

// Every vertex of `part` used by a face, paired with the vertex of `body` at the same posed
// position (within 1e-6 of the size) at the operation's pose; the count of those without one.
std::vector<std::pair<std::uint32_t, std::uint32_t>> find_partners(const std::vector<glm::vec3>& part_posed,
                                                                   const SurfaceMesh& part,
                                                                   const std::vector<glm::vec3>& body_posed,
                                                                   const SurfaceMesh& body, double size,
                                                                   std::size_t& unmatched) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  const auto candidates = used_vertices(body);
  unmatched = 0;
  for (std::uint32_t x : used_vertices(part)) {
    double best = 1e300;
    std::uint32_t at = 0;
    for (std::uint32_t y : candidates) {
      const double d = glm::length(part_posed[x] - body_posed[y]);
      if (d < best) best = d, at = y;
    }
    if (best <= 1e-6 * size)
      out.emplace_back(x, at);
    else
      ++unmatched;
  }
  return out;
}

// Poses at which the morph animation plays: the clip at several times, and weights set by hand.
std::vector<PoseKey> playing_poses() {
  return {PoseKey(0, 0.0f),  PoseKey(0, 0.3f),  PoseKey(0, 1.0f), PoseKey(0, 1.6f), PoseKey(0, 2.0f),
          PoseKey(-1, 0.0f), PoseKey(0, 0.7f, {{kTube, {1.5f, -0.7f}}})};
}

// The sampled weights of node `node`.
std::vector<float> weights_at(const Model& model, const PoseKey& key, int node) {
  return sample_pose(model, key).weights[static_cast<std::size_t>(node)];
}

void expect_weights(const std::vector<float>& got, const std::vector<float>& want, const std::string& where) {
  ASSERT_EQ(got.size(), want.size()) << where;
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_NEAR(got[i], want[i], 1e-6) << where << " target " << i;
}

}  // namespace

TEST(MorphPoseTest, weights_come_from_the_node_the_mesh_the_clip_and_the_hand) {
  Model model = test::make_morph_tube_model();
  expect_weights(rest_pose(model).weights[kTube], {0.1f, 0.2f}, "mesh default");
  EXPECT_TRUE(rest_pose(model).weights[1].empty()) << "a joint draws no morphing mesh";
  model.nodes[kTube].weights = {0.7f, 0.6f};
  expect_weights(rest_pose(model).weights[kTube], {0.7f, 0.6f}, "node weights");
  model.nodes[kTube].weights = {0.7f};  // not one per target: the mesh's
  expect_weights(rest_pose(model).weights[kTube], {0.1f, 0.2f}, "node weights of the wrong length");
  // Linear, clamped at both ends.
  expect_weights(weights_at(model, PoseKey(0, 0.5f), kTube), {0.75f, 0.4f}, "linear t=0.5");
  expect_weights(weights_at(model, PoseKey(0, 1.5f), kTube), {0.5f, 0.5f}, "linear t=1.5");
  expect_weights(weights_at(model, PoseKey(0, 9.0f), kTube), {0.0f, 1.0f}, "after the last key");
  expect_weights(weights_at(model, PoseKey(0, -1.0f), kTube), {0.5f, 0.8f}, "before the first key");
  expect_weights(weights_at(model, PoseKey(-1, 0.5f), kTube), {0.1f, 0.2f}, "rest pose");
  // Set by hand: replaces the sampled weights it gives; nodes without targets ignore it.
  expect_weights(weights_at(model, PoseKey(0, 0.5f, {{kTube, {0.9f}}, {1, {3.0f}}}), kTube), {0.9f, 0.4f},
                 "one weight by hand");
  expect_weights(weights_at(model, PoseKey(0, 0.5f, {{kTube, {0.9f, -1.0f, 5.0f}}}), kTube), {0.9f, -1.0f},
                 "extra weights by hand");
  EXPECT_TRUE(weights_at(model, PoseKey(0, 0.5f, {{1, {3.0f}}}), 1).empty());
  // Step.
  AnimationSampler& w = model.animations[0].samplers.back();
  w.interpolation = Interpolation::Step;
  expect_weights(weights_at(model, PoseKey(0, 0.99f), kTube), {0.5f, 0.8f}, "step before a key");
  expect_weights(weights_at(model, PoseKey(0, 1.0f), kTube), {1.0f, 0.0f}, "step at a key");
  // Cubic spline: per key in-tangents, values, out-tangents, two targets each. Target 0 goes
  // 0 -> 1 leaving with slope 3; target 1 goes 1 -> 0 with flat tangents.
  w.interpolation = Interpolation::CubicSpline;
  w.input = {0.0f, 1.0f};
  w.output = {0, 0, 0, 1, 3, 0, /**/ 0, 0, 1, 0, 0, 0};
  expect_weights(weights_at(model, PoseKey(0, 0.0f), kTube), {0.0f, 1.0f}, "cubic at key 0");
  expect_weights(weights_at(model, PoseKey(0, 1.0f), kTube), {1.0f, 0.0f}, "cubic at key 1");
  // h10 x 3 + h01 = 0.375 + 0.5; h00 = 0.5.
  expect_weights(weights_at(model, PoseKey(0, 0.5f), kTube), {0.875f, 0.5f}, "cubic between");
  // A sampler too short for the targets leaves the defaults.
  w.output.resize(6);
  expect_weights(weights_at(model, PoseKey(0, 0.5f), kTube), {0.1f, 0.2f}, "short sampler");
}

TEST(MorphPoseTest, morphs_apply_before_skinning_everywhere_a_pose_is_computed) {
  const Model model = test::make_morph_tube_model();
  const SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  EXPECT_EQ(morph_target_count(mesh), 2);
  for (const PoseKey& key : playing_poses()) {
    SCOPED_TRACE("animation " + std::to_string(key.animation) + " time " + std::to_string(key.time));
    const Pose pose = sample_pose(model, key);
    const auto world = world_matrices(model, pose);
    const auto want = pose_by_hand(model, kTube, mesh, pose);
    BoundingBox box;
    for (const auto& p : want) box.add(p);
    const float tol = 1e-6f * box.diagonal();
    const auto got = posed_positions(model, kTube, mesh, world, pose.weights[kTube]);
    const PosedModel posed = PosedModel::build(model, key);
    EXPECT_TRUE(posed.matches(key));
    EXPECT_EQ(posed.weights(kTube), pose.weights[kTube]);
    const PosedMesh& inst = *posed.find(kTube, 0);
    float unposed = 0.0f, morph_moved = 0.0f;
    const auto unmorphed = posed_positions(model, kTube, mesh, world, {});
    for (std::size_t v = 0; v < want.size(); ++v) {
      ASSERT_LE(glm::length(got[v] - want[v]), tol) << "posed_positions, vertex " << v;
      ASSERT_LE(glm::length(inst.posed[v] - want[v]), tol) << "PosedModel, vertex " << v;
      unposed = std::max(unposed, glm::length(inst.unpose(mesh, VertexId(std::uint32_t(v)), inst.posed[v]) -
                                              mesh.positions()[v]));
      morph_moved = std::max(morph_moved, glm::length(unmorphed[v] - want[v]));
    }
    EXPECT_LE(unposed, tol) << "unpose inverts the pose, morphs included";
    EXPECT_GT(morph_moved, 0.05f) << "the weights are not zero at these poses";
    const BoundingBox bounds = world_bounds(model, pose);
    EXPECT_LE(glm::length(bounds.min - box.min) + glm::length(bounds.max - box.max), 2.0f * tol);
    // Normals: stored + sum w_i dn_i, through the inverse transpose of the skin matrix.
    const auto normals = posed_normals(model, kTube, mesh, world, pose.weights[kTube]);
    const auto scene_normals = inst.corner_normals(mesh);
    const auto& stored = mesh.corner_attrs().get<glm::vec3>(attr::kNormal);
    const auto& dn = mesh.corner_attrs().get<glm::vec3>(attr::morph_normal_name(0));
    ASSERT_EQ(normals.size(), stored.size());
    ASSERT_EQ(scene_normals.size(), stored.size());
    const auto skin = vertex_skin_matrices(model, kTube, mesh, world);
    mesh.for_each_face([&](FaceId f, const Triangle& t) {
      for (int k = 0; k < 3; ++k) {
        const std::size_t c = SurfaceMesh::corner(f, k);
        const glm::vec3 n = stored[c] + pose.weights[kTube][0] * dn[c];
        const glm::vec3 expect = glm::normalize(glm::transpose(glm::inverse(glm::mat3(skin[t[k].index]))) * n);
        EXPECT_LE(glm::length(normals[c] - expect), 1e-5f) << "corner " << c;
        EXPECT_LE(glm::length(scene_normals[c] - expect), 1e-5f) << "corner " << c;
      }
    });
  }
}

TEST(MorphPoseTest, drill_at_a_morphed_pose_is_on_the_surface_and_its_walls_stay_attached) {
  for (const PoseKey& at : {PoseKey(0, 0.5f), PoseKey(0, 1.0f, {{kTube, {1.2f, -0.6f}}})}) {
    SCOPED_TRACE("drilled at time " + std::to_string(at.time));
    Model model = test::make_morph_tube_model();
    PosedModel posed = PosedModel::build(model, at);
    const PosedSurface before = posed_surface(model, at);
    const std::size_t old_count = model.meshes[0].primitives[0].mesh.vertex_count();
    // Sideways through the posed tube at the fifth ring (z is across the bend).
    glm::vec3 centre(0.0f);
    for (int i = 0; i < 16; ++i) centre += posed.find(kTube, 0)->posed[5 * 16 + i] / 16.0f;
    const Cylinder cyl{centre - glm::vec3(0, 0, 2), centre + glm::vec3(0, 0, 2), 0.2f};
    DrillOptions options;
    options.wall = true;
    const ModelDrillResult r = drill_model(model, posed, cyl, options, at.animation, at.time);
    ASSERT_EQ(r.status, OpStatus::Ok);
    ASSERT_EQ(model.meshes[0].primitives.size(), 2u) << "the surface and its wall";
    EXPECT_EQ(r.rim_vertices.size(), 2u);
    EXPECT_EQ(posed.key(), at) << "the weights set by hand stay";
    const SurfaceMesh& surface = model.meshes[0].primitives[0].mesh;
    const SurfaceMesh& wall = model.meshes[0].primitives[1].mesh;
    EXPECT_EQ(morph_target_count(surface), 2);
    EXPECT_EQ(morph_target_count(wall), 2);
    EXPECT_TRUE(zero_normal_deltas(wall));
    // New surface vertices on the posed input surface; those on the holes' rims on the cylinder.
    const auto& now = posed.find(kTube, 0)->posed;
    const glm::dvec3 axis = glm::normalize(glm::dvec3(cyl.b - cyl.a));
    const std::vector<char> rim = on_boundary(surface);
    double off_surface = 0.0, off_cylinder = 0.0;
    std::size_t rims = 0;
    for (std::uint32_t v : used_vertices(surface)) {
      if (v < old_count) continue;
      off_surface = std::max(off_surface, before.distance(now[v]));
      if (!rim[v]) continue;
      ++rims;
      const glm::dvec3 q = glm::dvec3(now[v]) - glm::dvec3(cyl.a);
      const double rho = glm::length(q - glm::dot(q, axis) * axis);
      off_cylinder = std::max(off_cylinder, std::abs(rho - double(cyl.radius)));
    }
    EXPECT_GE(rims, 16u);
    EXPECT_LE(off_surface, 1e-5 * before.size);
    EXPECT_LE(off_cylinder, 1e-5 * before.size);
    // The wall meets the surface at its rims (one posed position per rim vertex) and keeps
    // meeting it while the morph plays: its rim vertices carry the rim's own deltas.
    std::size_t unmatched = 0;
    const auto partners = find_partners(posed.find(kTube, 1)->posed, wall, now, surface, before.size, unmatched);
    EXPECT_GE(partners.size(), 8u);
    for (const PoseKey& key : playing_poses())
      EXPECT_EQ(largest_gap(model, key, kTube, wall, kTube, surface, partners), 0.0) << "time " << key.time;
    // The followed posed model equals a fresh build at the same pose, morphs included.
    EXPECT_EQ(test::difference_from_fresh_build(posed, model), "");
  }
}

// Poses at which the tube's skinning is rigid (the bend at rest) with non-zero weights: the cut
// and the tear place new vertices in bind space by interpolation, which is exact there.
std::vector<PoseKey> rigid_morphed_poses() {
  return {PoseKey(0, 0.0f), PoseKey(0, 2.0f, {{kTube, {0.6f, -0.3f}}})};
}

TEST(MorphPoseTest, cut_at_a_morphed_pose_keeps_targets_channels_and_attached_caps) {
  for (const PoseKey& at : rigid_morphed_poses()) {
    SCOPED_TRACE("cut at time " + std::to_string(at.time));
    Model model = test::make_morph_tube_model();
    PosedModel posed = PosedModel::build(model, at);
    const PosedSurface before = posed_surface(model, at);
    const Plane plane{{0.0f, 2.3f, 0.0f}, glm::normalize(glm::vec3(0.2f, 1.0f, 0.1f))};
    CutOptions options;
    options.cap = true;
    const ModelCutResult r = cut_model(model, posed, plane, options, at.animation, at.time);
    ASSERT_EQ(r.status, OpStatus::Ok);
    ASSERT_EQ(r.piece_nodes.size(), 2u);
    posed.prepare(model, at.animation, at.time);
    const PoseKey after = posed.key();  // the pieces get the source's weights set by hand
    for (int node : r.piece_nodes) {
      SCOPED_TRACE("piece node " + std::to_string(node));
      const Mesh& mesh = model.meshes[static_cast<std::size_t>(model.nodes[static_cast<std::size_t>(node)].mesh)];
      EXPECT_EQ(mesh.target_count(), 2u);
      EXPECT_EQ(mesh.target_names, (std::vector<std::string>{"swell", "lean"}));
      bool channel = false;
      for (const AnimationChannel& ch : model.animations[0].channels)
        channel |= ch.node == node && ch.path == AnimationPath::Weights;
      EXPECT_TRUE(channel) << "the piece plays the clip's weights";
      EXPECT_EQ(weights_at(model, after, node), weights_at(model, at, kTube));
      ASSERT_EQ(mesh.primitives.size(), 2u) << "body and cap";
      const SurfaceMesh& body = mesh.primitives[0].mesh;
      const SurfaceMesh& cap = mesh.primitives[1].mesh;
      for (const Primitive& prim : mesh.primitives) {
        EXPECT_EQ(morph_target_count(prim.mesh), 2);
        EXPECT_NE(prim.mesh.corner_attrs().find<glm::vec3>(attr::morph_normal_name(0)), nullptr);
      }
      EXPECT_TRUE(zero_normal_deltas(cap));
      // Every vertex of the piece on the posed input surface; the cap's on the plane.
      const auto& body_posed = posed.find(node, 0)->posed;
      const auto& cap_posed = posed.find(node, 1)->posed;
      double off_surface = 0.0, off_plane = 0.0;
      for (std::uint32_t v : used_vertices(body)) off_surface = std::max(off_surface, before.distance(body_posed[v]));
      for (std::uint32_t v : used_vertices(cap))
        off_plane = std::max(off_plane, double(std::abs(glm::dot(cap_posed[v] - plane.point, plane.normal))));
      EXPECT_LE(off_surface, 1e-5 * before.size);
      EXPECT_LE(off_plane, 1e-5 * before.size);
      // The cap is made of rim vertices only, each one a vertex of the body, at every pose.
      std::size_t unmatched = 0;
      const auto partners = find_partners(cap_posed, cap, body_posed, body, before.size, unmatched);
      EXPECT_EQ(unmatched, 0u);
      EXPECT_GE(partners.size(), 16u);
      for (const PoseKey& key : playing_poses()) {
        PoseKey played = key;
        if (played.weights.count(kTube)) played.weights[node] = played.weights[kTube];
        EXPECT_EQ(largest_gap(model, played, node, cap, node, body, partners), 0.0) << "time " << key.time;
      }
    }
  }
}

TEST(MorphPoseTest, tear_at_a_morphed_pose_is_on_the_surface) {
  for (const PoseKey& at : rigid_morphed_poses()) {
    SCOPED_TRACE("tear at time " + std::to_string(at.time));
    Model model = test::make_morph_tube_model();
    PosedModel posed = PosedModel::build(model, at);
    const PosedSurface before = posed_surface(model, at);
    const std::size_t old_count = model.meshes[0].primitives[0].mesh.vertex_count();
    // Along the near wall (angle 90 degrees, -z) from ring 3 to ring 5, as the designer sees it.
    const auto& p = posed.find(kTube, 0)->posed;
    const glm::vec3 q = p[3 * 16 + 4], top = p[5 * 16 + 4], out(0.0f, 0.0f, -1.0f);
    const glm::vec3 along = top - q;
    const Blade start{q + 0.2f * along + 0.4f * out, q + 0.2f * along - 0.3f * out};
    const Blade end{q + 0.8f * along + 0.4f * out, q + 0.8f * along - 0.3f * out};
    TearOptions options;
    options.width = 0.0f;  // lips apart without moving: every new vertex stays on the surface
    const ModelTearResult r = tear_model(model, posed, start, end, options, at.animation, at.time);
    ASSERT_EQ(r.status, OpStatus::Ok);
    EXPECT_EQ(r.slits, 1u);
    const SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
    EXPECT_EQ(morph_target_count(mesh), 2);
    const auto quad = swept_quad_triangles(start, end);
    const glm::dvec3 n =
        glm::normalize(glm::cross(glm::dvec3(quad[0][1] - quad[0][0]), glm::dvec3(quad[0][2] - quad[0][0])));
    const auto& now = posed.find(kTube, 0)->posed;
    double off_surface = 0.0, off_quad = 0.0;
    std::size_t added = 0;
    for (std::uint32_t v : used_vertices(mesh)) {
      if (v < old_count) continue;
      ++added;
      off_surface = std::max(off_surface, before.distance(now[v]));
      off_quad = std::max(off_quad, std::abs(glm::dot(glm::dvec3(now[v]) - glm::dvec3(quad[0][0]), n)));
    }
    EXPECT_GT(added, 4u);
    EXPECT_LE(off_surface, 1e-5 * before.size);
    EXPECT_LE(off_quad, 1e-5 * before.size);
    const PosedModel fresh = PosedModel::build(model, posed.key());
    const PosedMesh& want = *fresh.find(kTube, 0);
    ASSERT_EQ(now.size(), want.posed.size());
    for (std::size_t v = 0; v < now.size(); ++v) ASSERT_EQ(now[v], want.posed[v]) << v;
  }
}

TEST(MorphPoseTest, a_dropped_node_loses_its_weights_and_a_reposed_model_equals_a_build) {
  Model model = test::make_morph_tube_model();
  PosedModel posed = PosedModel::build(model, PoseKey(0, 0.4f, {{kTube, {0.3f, 0.9f}}}), PoseDetail::Positions);
  for (const PoseKey& key : playing_poses()) {
    posed.repose(model, key);
    const PosedModel fresh = PosedModel::build(model, key, PoseDetail::Positions);
    EXPECT_TRUE(posed.matches(key));
    const auto& a = posed.find(kTube, 0)->posed;
    const auto& b = fresh.find(kTube, 0)->posed;
    for (std::size_t v = 0; v < a.size(); ++v) ASSERT_EQ(a[v], b[v]) << "time " << key.time << " vertex " << v;
  }
  // A twin of the tube far below, with its own weights and weight channel: a cut keeping the
  // upper side drops it, and with it everything that animated its weights.
  Node twin;
  twin.mesh = 0;
  twin.translation = {0.0f, -10.0f, 0.0f};
  twin.weights = {0.3f, 0.3f};
  model.nodes.push_back(twin);
  const int twin_node = static_cast<int>(model.nodes.size() - 1);
  model.scenes[0].push_back(twin_node);
  AnimationChannel ch = model.animations[0].channels.back();
  ASSERT_EQ(ch.path, AnimationPath::Weights);
  ch.node = twin_node;
  model.animations[0].channels.push_back(ch);
  CutOptions options;
  options.keep = CutKeep::Positive;
  const Plane plane{{0.0f, 2.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  ASSERT_EQ(cut_model(model, plane, options, 0, 0.0f).status, OpStatus::Ok);
  EXPECT_EQ(model.nodes[static_cast<std::size_t>(twin_node)].mesh, -1);
  EXPECT_TRUE(model.nodes[static_cast<std::size_t>(twin_node)].weights.empty());
  std::size_t channels = 0;
  for (const AnimationChannel& c : model.animations[0].channels) {
    if (c.path != AnimationPath::Weights) continue;
    ++channels;
    EXPECT_NE(c.node, twin_node);
    EXPECT_GE(model.nodes[static_cast<std::size_t>(c.node)].mesh, 0);
  }
  EXPECT_EQ(channels, 1u) << "the kept piece's";
}

TEST(MorphPoseTest, cut_and_drilled_pieces_at_a_morphed_pose_survive_the_file) {
  // Cut with caps and drill with walls at a morphed pose, write, read back: every piece keeps its
  // targets and weight channel, the file is valid glTF, and the re-read model poses as the edited
  // one does while the morph plays.
  Model model = test::make_morph_tube_model();
  PosedModel posed = PosedModel::build(model, 0, 0.0f);
  CutOptions cut;
  cut.cap = true;
  ASSERT_EQ(cut_model(model, posed, {{0.0f, 2.3f, 0.0f}, {0.0f, 1.0f, 0.0f}}, cut, 0, 0.0f).status, OpStatus::Ok);
  DrillOptions drill;
  drill.wall = true;
  const Cylinder cyl{{0.1f, 1.0f, -2.0f}, {0.1f, 1.0f, 2.0f}, 0.2f};
  ASSERT_EQ(drill_model(model, posed, cyl, drill, 0, 0.5f).status, OpStatus::Ok);
  const std::string dir = test::temp_dir("morph-pose");
  const std::string path = dir + "/pieces.glb";
  write_gltf(model, path);
  const test::RunResult validated = test::validate_gltf(path);
  EXPECT_EQ(validated.exit_code, 0) << validated.out << validated.err;
  const Model back = read_gltf(path);
  std::size_t pieces = 0;
  for (std::size_t n = 0; n < back.nodes.size(); ++n) {
    if (back.nodes[n].mesh < 0) continue;
    ++pieces;
    EXPECT_EQ(back.meshes[static_cast<std::size_t>(back.nodes[n].mesh)].target_count(), 2u) << "node " << n;
    bool channel = false;
    for (const AnimationChannel& ch : back.animations.at(0).channels)
      channel |= ch.node == static_cast<int>(n) && ch.path == AnimationPath::Weights;
    EXPECT_TRUE(channel) << "node " << n;
  }
  EXPECT_EQ(pieces, 2u);
  for (const PoseKey& key : {PoseKey(0, 0.3f), PoseKey(0, 1.0f), PoseKey(0, 1.8f)}) {
    const BoundingBox a = world_bounds(model, sample_pose(model, key));
    const BoundingBox b = world_bounds(back, sample_pose(back, key));
    EXPECT_LE(glm::length(a.min - b.min) + glm::length(a.max - b.max), 1e-5f * a.diagonal()) << "time " << key.time;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace deepcut
