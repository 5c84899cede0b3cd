// SPDX-License-Identifier: MIT
#include "deepcut/core/generate/cactus.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/attributes.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/validate.h"
#include "fixtures.h"
#include "tools.h"

namespace deepcut {

TEST(CactusTest, default_cactus_is_a_closed_rigged_model_like_the_papers) {
  const Model model = make_cactus();
  ASSERT_EQ(model.meshes.size(), 1u);
  ASSERT_EQ(model.meshes[0].primitives.size(), 1u);
  const SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  // The paper's cactus: 25 267 triangles.
  EXPECT_NEAR(double(mesh.face_count()), 25300.0, 25300.0 * 0.03);
  const Adjacency adj = Adjacency::build(mesh);
  EXPECT_TRUE(adj.boundary_edges().empty()) << "every limb is closed";
  EXPECT_TRUE(adj.nonmanifold_edges().empty());
  EXPECT_EQ(adj.component_count(), 3u);  // trunk and two arms
  EXPECT_GT(mesh.volume(), 0.0) << "outward orientation";
  EXPECT_FALSE(adj.seam_edges(mesh).empty()) << "cylindrical UVs have a seam";
  ASSERT_EQ(model.skins.size(), 1u);
  EXPECT_GE(model.skins[0].joints.size(), 8u);
  ASSERT_EQ(model.animations.size(), 1u);
  EXPECT_GT(model.animations[0].duration(), 0.0f);
  test::expect_valid(mesh, model.skins[0].joints.size());
  EXPECT_TRUE(find_problems(model).empty());
  // No degenerate triangles.
  const auto& p = mesh.positions();
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    const float area = glm::length(glm::cross(p[t[1].index] - p[t[0].index], p[t[2].index] - p[t[0].index]));
    ASSERT_GT(area, 0.0f) << "face " << f.index;
  });
}

TEST(CactusTest, sway_loops_and_moves_the_model) {
  const Model model = make_cactus();
  const auto& mesh = model.meshes[0].primitives[0].mesh;
  int mesh_node = -1;
  for (std::size_t n = 0; n < model.nodes.size(); ++n)
    if (model.nodes[n].mesh == 0) mesh_node = static_cast<int>(n);
  ASSERT_GE(mesh_node, 0);
  const float d = model.animations[0].duration();
  const auto at = [&](float t) { return posed_positions(model, mesh_node, mesh, world_matrices(model, sample_pose(model, 0, t))); };
  const auto rest = posed_positions(model, mesh_node, mesh, world_matrices(model, rest_pose(model)));
  const auto start = at(0.0f), end = at(d), middle = at(0.3f * d);
  float loop_gap = 0.0f, motion = 0.0f, bind_gap = 0.0f;
  for (std::size_t v = 0; v < start.size(); ++v) {
    loop_gap = std::max(loop_gap, glm::length(start[v] - end[v]));
    motion = std::max(motion, glm::length(start[v] - middle[v]));
    bind_gap = std::max(bind_gap, glm::length(rest[v] - mesh.positions()[v]));
  }
  const float size = mesh.bounds().diagonal();
  EXPECT_LT(loop_gap, 1e-4f * size) << "the sway loops";
  EXPECT_GT(motion, 1e-3f * size) << "the sway moves the cactus";
  EXPECT_LT(bind_gap, 1e-5f * size) << "the rest pose is the bind pose";
}

namespace {
bool same_bytes(const std::string& a, const std::string& b) {
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  const std::string sa((std::istreambuf_iterator<char>(fa)), {}), sb((std::istreambuf_iterator<char>(fb)), {});
  return !sa.empty() && sa == sb;
}

// The trunk is the component holding the highest vertex; the arms are the other two.
std::vector<bool> trunk_vertices(const SurfaceMesh& mesh) {
  const std::vector<std::uint32_t> component = Adjacency::build(mesh).vertex_components();
  const auto& p = mesh.positions();
  std::size_t top = 0;
  for (std::size_t v = 1; v < p.size(); ++v)
    if (p[v].y > p[top].y) top = v;
  std::vector<bool> trunk(p.size());
  for (std::size_t v = 0; v < p.size(); ++v) trunk[v] = component[v] == component[top];
  return trunk;
}
}  // namespace

TEST(CactusTest, blend_shapes_lift_the_arms_and_swell_a_bloom_on_top) {
  const Model model = make_cactus();
  const Mesh& m = model.meshes[0];
  const SurfaceMesh& mesh = m.primitives[0].mesh;
  ASSERT_EQ(m.target_count(), 2u);
  EXPECT_EQ(m.weights, std::vector<float>(2, 0.0f));
  EXPECT_EQ(m.target_names, (std::vector<std::string>{"arms_lift", "bloom"}));
  EXPECT_EQ(m.extras_json, R"({"targetNames":["arms_lift","bloom"]})");
  const std::vector<bool> trunk = trunk_vertices(mesh);
  const float size = mesh.bounds().diagonal();
  const auto& lift = mesh.vertex_attrs().get<glm::vec3>(attr::morph_position_name(0)).data();
  const auto& bloom = mesh.vertex_attrs().get<glm::vec3>(attr::morph_position_name(1)).data();
  ASSERT_EQ(lift.size(), mesh.vertex_count());
  ASSERT_EQ(bloom.size(), mesh.vertex_count());
  float arm_lift = 0.0f, lowest_bloom = size;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    ASSERT_TRUE(std::isfinite(lift[v].x) && std::isfinite(lift[v].y) && std::isfinite(lift[v].z));
    ASSERT_TRUE(std::isfinite(bloom[v].x) && std::isfinite(bloom[v].y) && std::isfinite(bloom[v].z));
    if (trunk[v]) {
      EXPECT_EQ(lift[v], glm::vec3(0.0f)) << "the arms' shape moves no trunk vertex (" << v << ")";
    } else {
      EXPECT_EQ(bloom[v], glm::vec3(0.0f)) << "the bloom moves no arm vertex (" << v << ")";
      EXPECT_GE(lift[v].y, 0.0f) << "arms rise";
      arm_lift = std::max(arm_lift, lift[v].y);
    }
    if (bloom[v] != glm::vec3(0.0f)) lowest_bloom = std::min(lowest_bloom, mesh.positions()[v].y);
  }
  EXPECT_GT(arm_lift, 0.02f * size) << "the arms visibly rise";
  EXPECT_GT(lowest_bloom, 0.8f * mesh.bounds().max.y) << "the bloom is on top";
  // Normal deltas per corner: the rest normal plus the delta is the unit normal of the fully
  // morphed surface.
  for (int t = 0; t < 2; ++t) {
    const auto& dn = mesh.corner_attrs().get<glm::vec3>(attr::morph_normal_name(t)).data();
    const auto& n = mesh.corner_attrs().get<glm::vec3>(attr::kNormal).data();
    ASSERT_EQ(dn.size(), n.size());
    for (std::size_t c = 0; c < n.size(); ++c) ASSERT_NEAR(glm::length(n[c] + dn[c]), 1.0f, 1e-3f) << "corner " << c;
  }
}

TEST(CactusTest, clip_plays_the_blend_shapes_in_a_loop) {
  const Model model = make_cactus();
  const Animation& clip = model.animations[0];
  int mesh_node = -1;
  for (std::size_t n = 0; n < model.nodes.size(); ++n)
    if (model.nodes[n].mesh == 0) mesh_node = static_cast<int>(n);
  const AnimationChannel* channel = nullptr;
  for (const AnimationChannel& c : clip.channels)
    if (c.path == AnimationPath::Weights) {
      EXPECT_EQ(channel, nullptr) << "one weight channel";
      channel = &c;
    }
  ASSERT_NE(channel, nullptr);
  EXPECT_EQ(channel->node, mesh_node);
  const AnimationSampler& s = clip.samplers[static_cast<std::size_t>(channel->sampler)];
  EXPECT_EQ(s.components, 2);
  EXPECT_EQ(s.interpolation, Interpolation::Linear);
  ASSERT_GE(s.input.size(), 3u);
  EXPECT_EQ(s.input.front(), 0.0f);
  EXPECT_EQ(s.input.back(), clip.duration()) << "keyed over the whole clip";
  ASSERT_EQ(s.output.size(), 2 * s.input.size());
  float peak[2] = {0.0f, 0.0f};
  for (std::size_t k = 0; k < s.output.size(); ++k) {
    EXPECT_GE(s.output[k], 0.0f);
    EXPECT_LE(s.output[k], 1.0f);
    peak[k % 2] = std::max(peak[k % 2], s.output[k]);
  }
  EXPECT_GT(peak[0], 0.99f);
  EXPECT_GT(peak[1], 0.99f);
  for (int t = 0; t < 2; ++t) {
    EXPECT_EQ(s.output[std::size_t(t)], 0.0f) << "the clip starts at rest";
    EXPECT_EQ(s.output[s.output.size() - 2 + std::size_t(t)], s.output[std::size_t(t)]) << "the loop is seamless";
  }
}

TEST(CactusTest, size_parameter_scales_the_triangle_count) {
  CactusOptions options;
  options.target_triangles = 100000;
  const Model big = make_cactus(options);
  EXPECT_NEAR(double(big.meshes[0].primitives[0].mesh.face_count()), 100000.0, 5000.0);
  options.target_triangles = 10;
  EXPECT_THROW(make_cactus(options), Error);
}

TEST(CactusTest, bundled_asset_is_what_the_generator_makes) {
  // assets/cactus.glb is committed; it must stay in step with the generator.
  const Model bundled = read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  const Model fresh = make_cactus();
  const auto& a = bundled.meshes[0].primitives[0].mesh;
  const auto& b = fresh.meshes[0].primitives[0].mesh;
  EXPECT_EQ(a.face_count(), b.face_count());
  EXPECT_EQ(a.vertex_count(), b.vertex_count());
  EXPECT_NEAR(a.volume(), b.volume(), 1e-4 * std::abs(b.volume()));
  const auto v = test::validate_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb");
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
  // Byte for byte: `deepcut make-cactus -o assets/cactus.glb` writes what the generator makes.
  const std::string written = test::temp_dir("cactus-asset") + "/cactus.glb";
  write_gltf(fresh, written);
  EXPECT_TRUE(same_bytes(written, std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb"))
      << "assets/cactus.glb is stale: regenerate it with deepcut make-cactus -o assets/cactus.glb";
  // The blend shapes and their channel survive the file.
  EXPECT_EQ(bundled.meshes[0].target_names, fresh.meshes[0].target_names);
  EXPECT_EQ(bundled.meshes[0].weights, fresh.meshes[0].weights);
  std::size_t weight_channels = 0;
  for (const AnimationChannel& c : bundled.animations.at(0).channels) weight_channels += c.path == AnimationPath::Weights;
  EXPECT_EQ(weight_channels, 1u);
}

}  // namespace deepcut
