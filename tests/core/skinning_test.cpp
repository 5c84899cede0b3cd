// SPDX-License-Identifier: MIT
#include "deepcut/core/skinning.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

#include "deepcut/core/generate/cactus.h"
#include "fixtures.h"

namespace deepcut {
namespace {

Model one_channel_model(Interpolation interpolation, std::vector<float> input, std::vector<float> output, AnimationPath path,
                        int components) {
  Model model;
  model.nodes.resize(1);
  Animation a;
  AnimationSampler s;
  s.input = std::move(input);
  s.output = std::move(output);
  s.components = components;
  s.interpolation = interpolation;
  a.samplers.push_back(s);
  a.channels.push_back({0, 0, path});
  model.animations.push_back(a);
  return model;
}

}  // namespace

TEST(SkinningTest, step_linear_and_clamping_for_translation) {
  const std::vector<float> in = {0, 1, 2};
  const std::vector<float> out = {0, 0, 0, 10, 0, 0, 10, 20, 0};
  const Model linear = one_channel_model(Interpolation::Linear, in, out, AnimationPath::Translation, 3);
  EXPECT_NEAR(sample_pose(linear, 0, 0.5f).translation[0].x, 5.0f, 1e-6);
  EXPECT_NEAR(sample_pose(linear, 0, 1.5f).translation[0].y, 10.0f, 1e-6);
  EXPECT_NEAR(sample_pose(linear, 0, 7.0f).translation[0].y, 20.0f, 1e-6);  // clamped
  EXPECT_NEAR(sample_pose(linear, 0, -1.0f).translation[0].x, 0.0f, 1e-6);
  const Model step = one_channel_model(Interpolation::Step, in, out, AnimationPath::Translation, 3);
  EXPECT_NEAR(sample_pose(step, 0, 0.99f).translation[0].x, 0.0f, 1e-6);
  EXPECT_NEAR(sample_pose(step, 0, 1.0f).translation[0].x, 10.0f, 1e-6);
  EXPECT_THROW(sample_pose(linear, 3, 0.0f), Error);
}

TEST(SkinningTest, cubic_spline_hits_keys_and_uses_tangents) {
  // Keys: value 0 then 1, out-tangent of key 0 is 3 (per second), in-tangent of key 1 is 0.
  // Each key: in-tangent, value, out-tangent (x only, y and z zero).
  const std::vector<float> out = {0, 0, 0, 0, 0, 0, 3, 0, 0, /**/ 0, 0, 0, 1, 0, 0, 0, 0, 0};
  const Model m = one_channel_model(Interpolation::CubicSpline, {0, 1}, out, AnimationPath::Translation, 3);
  EXPECT_NEAR(sample_pose(m, 0, 0.0f).translation[0].x, 0.0f, 1e-6);
  EXPECT_NEAR(sample_pose(m, 0, 1.0f).translation[0].x, 1.0f, 1e-6);
  // p(0.5) = h00*0 + h10*1*3 + h01*1 + h11*0 = 0.125*3 + 0.5
  EXPECT_NEAR(sample_pose(m, 0, 0.5f).translation[0].x, 0.875f, 1e-6);
}

TEST(SkinningTest, rotation_slerps_along_the_short_arc) {
  const glm::quat q0(1, 0, 0, 0);
  const glm::quat q1 = -glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 1, 0));  // same rotation, far sign
  const Model m = one_channel_model(Interpolation::Linear, {0, 1},
                                    {q0.x, q0.y, q0.z, q0.w, q1.x, q1.y, q1.z, q1.w}, AnimationPath::Rotation, 4);
  const glm::quat half = sample_pose(m, 0, 0.5f).rotation[0];
  EXPECT_NEAR(glm::degrees(glm::angle(half)), 45.0f, 1e-3);
  const glm::vec3 x = half * glm::vec3(1, 0, 0);
  EXPECT_NEAR(x.z, -std::sin(glm::radians(45.0f)), 1e-5);
}

TEST(SkinningTest, rest_pose_skinning_reproduces_bind_positions_and_bends_with_animation) {
  const Model model = test::make_skinned_tube_model();
  const auto& mesh = model.meshes[0].primitives[0].mesh;
  const auto rest = world_matrices(model, rest_pose(model));
  const auto posed = posed_positions(model, 0, mesh, rest);
  for (std::size_t v = 0; v < posed.size(); ++v) EXPECT_NEAR(glm::length(posed[v] - mesh.positions()[v]), 0.0f, 1e-5f);
  // At t = 1 the tip joint is rotated 60 degrees about z at y = 2: the top centre moves.
  const auto bent = posed_positions(model, 0, mesh, world_matrices(model, sample_pose(model, 0, 1.0f)));
  const std::size_t top = mesh.vertex_count() - 1;  // make_tube's last vertex: top centre (y = 4)
  const glm::vec3 expected = glm::vec3(0, 2, 0) + glm::angleAxis(glm::radians(60.0f), glm::vec3(0, 0, 1)) * glm::vec3(0, 2, 0);
  EXPECT_NEAR(glm::length(bent[top] - expected), 0.0f, 1e-4f);
  // Normals follow.
  const auto normals = posed_normals(model, 0, mesh, rest);
  EXPECT_TRUE(normals.empty());  // the tube has no normals
  const BoundingBox box = world_bounds(model, rest_pose(model));
  EXPECT_NEAR(box.max.y, 4.0f, 1e-5);
}

// The bits of `x` with -0 read as +0: BoundingBox::add keeps the first of equal values, so the
// sign of a zero bound depends on the order the positions are visited in.
namespace {
std::uint32_t bits_but_zero_sign(float x) {
  if (x == 0.0f) x = 0.0f;
  std::uint32_t u;
  std::memcpy(&u, &x, sizeof u);
  return u;
}
}  // namespace

// world_bounds measures each instance without its posed array (the vertices a live face uses,
// posed in one pass, in vertex order): the same bounds in value as face_bounds of posed_positions
// (face order), bit for bit except the sign of a zero, also with a deleted face and a vertex no
// face uses (left out, as face_bounds leaves them).
TEST(SkinningTest, world_bounds_equal_face_bounds_of_the_posed_positions_but_for_a_zeros_sign) {
  Model model = test::make_morph_tube_model();
  auto expected = [](const Model& m, const Pose& pose) {
    const auto world = world_matrices(m, pose);
    BoundingBox box;
    for (std::size_t i = 0; i < m.nodes.size(); ++i) {
      const int mesh = m.nodes[i].mesh;
      if (mesh < 0) continue;
      for (const auto& prim : m.meshes[static_cast<std::size_t>(mesh)].primitives)
        box.add(face_bounds(prim.mesh,
                            posed_positions(m, static_cast<int>(i), prim.mesh, world, pose.weights[i])));
    }
    return box;
  };
  auto check = [&](const Model& m) {
    std::vector<Pose> poses = {rest_pose(m)};
    if (!m.animations.empty())
      for (float t : {0.37f, 1.0f, 1.6f}) poses.push_back(sample_pose(m, 0, t));
    for (const Pose& pose : poses) {
      const BoundingBox a = world_bounds(m, pose), b = expected(m, pose);
      ASSERT_FALSE(a.empty());
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(a.min[k], b.min[k]);  // == takes -0 and +0 as equal
        EXPECT_EQ(a.max[k], b.max[k]);
        EXPECT_EQ(bits_but_zero_sign(a.min[k]), bits_but_zero_sign(b.min[k]));
        EXPECT_EQ(bits_but_zero_sign(a.max[k]), bits_but_zero_sign(b.max[k]));
      }
    }
  };
  check(model);
  // The cactus: most of its vertices share their joints and weights with the vertex before
  // them, whose blended matrix world_bounds reuses.
  check(make_cactus());
  SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  // The face at the top of the tube deleted, a vertex far away that no face uses.
  const glm::vec3 top = mesh.positions().back();
  for (std::uint32_t f = 0; f < mesh.face_slots(); ++f)
    for (VertexId v : mesh.face(FaceId(f)))
      if (mesh.position(v) == top) {
        mesh.mark_deleted(FaceId(f));
        break;
      }
  mesh.add_vertex(glm::vec3(100.0f));
  check(model);
  EXPECT_LT(world_bounds(model, rest_pose(model)).max.x, 50.0f);

  // A zero bound reached with both signs: a node matrix whose translation y is -0 poses b at
  // y = +0 and a at y = -0; the face visits a first, vertex order b first, so min.y may be -0 one
  // way and +0 the other. Equal all the same.
  Model zeros;
  Node node;
  node.mesh = 0;
  glm::mat4 matrix(1.0f);
  matrix[3][1] = -0.0f;
  node.matrix = matrix;
  zeros.nodes.push_back(node);
  Mesh tri;
  Primitive prim;
  const VertexId b = prim.mesh.add_vertex({1.0f, 0.0f, 1.0f});
  const VertexId a = prim.mesh.add_vertex({-1.0f, -0.0f, -1.0f});
  const VertexId c = prim.mesh.add_vertex({0.0f, 1.0f, 0.0f});
  prim.mesh.add_face(a, b, c);
  tri.primitives.push_back(std::move(prim));
  zeros.meshes.push_back(std::move(tri));
  check(zeros);
  EXPECT_EQ(world_bounds(zeros, rest_pose(zeros)).min.y, 0.0f);
}

}  // namespace deepcut
