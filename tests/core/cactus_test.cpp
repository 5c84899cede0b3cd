// SPDX-License-Identifier: MIT
#include "deepcut/core/generate/cactus.h"

#include <cmath>

#include <gtest/gtest.h>

#include "deepcut/core/adjacency.h"
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
}

}  // namespace deepcut
