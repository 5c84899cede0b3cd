// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/softbody/simulation.h"
#include "fixtures.h"

namespace deepcut {
namespace {

const std::string kCactus = std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb";

struct Cactus {
  Model model;
  const SurfaceMesh* mesh = nullptr;
  int node = -1;
  std::vector<glm::vec3> rest;
  float size = 0.0f;
};

Cactus load_cactus() {
  Cactus c;
  c.model = read_gltf(kCactus);
  for (std::size_t n = 0; n < c.model.nodes.size(); ++n)
    if (c.model.nodes[n].mesh >= 0) {
      c.node = static_cast<int>(n);
      c.mesh = &c.model.meshes[c.model.nodes[n].mesh].primitives[0].mesh;
      break;
    }
  c.rest = posed_positions(c.model, c.node, *c.mesh, world_matrices(c.model, rest_pose(c.model)));
  BoundingBox box;
  for (const auto& p : c.rest) box.add(p);
  c.size = box.diagonal();
  return c;
}

std::uint32_t nearest_vertex(const std::vector<glm::vec3>& positions, const glm::vec3& p) {
  std::uint32_t best = 0;
  for (std::uint32_t v = 1; v < positions.size(); ++v)
    if (glm::length(positions[v] - p) < glm::length(positions[best] - p)) best = v;
  return best;
}

bool all_finite(const std::vector<glm::vec3>& v) {
  return std::all_of(v.begin(), v.end(), [](const glm::vec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
  });
}

TEST(SoftbodySimulationTest, poke_rises_then_decays_monotonically_to_rest) {
  const Cactus c = load_cactus();
  const Clusters clusters = Clusters::build(*c.mesh, c.rest, ClusterOptions{0.73f});
  const glm::vec3 point = c.rest[nearest_vertex(c.rest, {1.2f, 5.0f, 0.0f})];
  for (const float dt : {1.0f / 30.0f, 1.0f / 60.0f, 1.0f / 240.0f}) {
    SCOPED_TRACE("dt " + std::to_string(dt));
    SoftBodyState state = make_soft_body(clusters);
    ASSERT_GT(poke(state, clusters, c.rest, point, {-4.0f, 0.0f, 0.0f}, 1.5f), 0u);
    std::vector<float> series;
    std::vector<glm::vec3> out;
    for (float t = 0.0f; t < 4.0f; t += dt) {
      step_soft_body(state, dt);
      series.push_back(deformed_positions(state, clusters, c.rest, out));
      ASSERT_TRUE(all_finite(out));
    }
    const std::size_t peak =
        static_cast<std::size_t>(std::max_element(series.begin(), series.end()) - series.begin());
    EXPECT_GT(peak, 0u) << "the displacement must rise first";
    EXPECT_GT(series[peak], 1e-3f * c.size);
    for (std::size_t f = peak + 1; f < series.size(); ++f)
      ASSERT_LE(series[f], series[f - 1] * (1.0f + 1e-5f) + 1e-7f * c.size)
          << "frame " << f << " grew after the peak";
    EXPECT_LT(series.back(), 1e-4f * c.size);
    EXPECT_FLOAT_EQ(max_vertex_displacement(state, clusters), series.back());
  }
}

TEST(SoftbodySimulationTest, any_step_up_to_a_thirtieth_and_beyond_is_finite_and_dissipative) {
  const SurfaceMesh mesh = test::make_grid(12, 12);
  const Clusters clusters = Clusters::build(mesh, ClusterOptions{0.25f});
  SoftBodyOptions critical, stiff, undamped, overdamped, light;
  stiff.stiffness = 1e5f;
  undamped.damping = 0.0f;
  overdamped.damping = 1e3f;
  light.mass = 1e-3f;
  for (const SoftBodyOptions& o : {critical, stiff, undamped, overdamped, light})
    for (const float dt : {1e-4f, 1.0f / 240.0f, 1.0f / 60.0f, 1.0f / 30.0f, 0.25f, 10.0f}) {
      SCOPED_TRACE("k " + std::to_string(o.stiffness) + " c " + std::to_string(o.damping) + " m " +
                   std::to_string(o.mass) + " dt " + std::to_string(dt));
      SoftBodyState state = make_soft_body(clusters);
      ASSERT_GT(poke(state, clusters, mesh.positions(), {0.5f, 0.5f, 0.0f}, {0.0f, 0.0f, o.mass}, 0.6f, o),
                0u);
      auto energy = [&]() {
        double e = 0.0;
        for (std::size_t p = 0; p < state.displacement.size(); ++p)
          e += 0.5 * o.stiffness * glm::dot(state.displacement[p], state.displacement[p]) +
               0.5 * o.mass * glm::dot(state.velocity[p], state.velocity[p]);
        return e;
      };
      const double e0 = energy();
      double previous = e0;
      for (int f = 0; f < 200; ++f) {
        step_soft_body(state, dt, o);
        ASSERT_TRUE(all_finite(state.displacement) && all_finite(state.velocity)) << "frame " << f;
        const double e = energy();
        if (o.damping > 0.0f)
          ASSERT_LE(e, previous * (1.0 + 1e-5) + 1e-12) << "energy grew at frame " << f;
        else
          ASSERT_NEAR(e, e0, 1e-4 * e0) << "undamped energy drifted at frame " << f;
        previous = e;
      }
      std::vector<glm::vec3> out;
      deformed_positions(state, clusters, mesh.positions(), out);
      EXPECT_TRUE(all_finite(out));
    }
}

TEST(SoftbodySimulationTest, springs_follow_the_closed_form_solution) {
  // One particle: a grid much smaller than rho.
  const SurfaceMesh mesh = test::make_grid(2, 2);
  const Clusters clusters = Clusters::build(mesh, ClusterOptions{10.0f});
  ASSERT_EQ(clusters.particle_count(), 1u);
  const glm::vec3 centre = posed_particle_centres(clusters, mesh.positions())[0];
  struct Case {
    float k, c;
    double (*x)(double t);  // displacement for a unit initial velocity, m = 1
  };
  const Case cases[] = {
      {100.0f, 20.0f, [](double t) { return t * std::exp(-10.0 * t); }},  // critical
      {100.0f, 4.0f,
       [](double t) {
         const double wd = std::sqrt(100.0 - 4.0);
         return std::exp(-2.0 * t) * std::sin(wd * t) / wd;
       }},  // underdamped
      {100.0f, 50.0f,
       [](double t) {
         const double r1 = (-50.0 + std::sqrt(2500.0 - 400.0)) / 2.0,
                      r2 = (-50.0 - std::sqrt(2500.0 - 400.0)) / 2.0;
         return (std::exp(r1 * t) - std::exp(r2 * t)) / (r1 - r2);
       }},  // overdamped
  };
  for (const Case& k : cases)
    for (const int steps : {15, 150}) {
      SoftBodyOptions o;
      o.stiffness = k.k;
      o.damping = k.c;
      SoftBodyState state = make_soft_body(clusters);
      ASSERT_EQ(poke(state, clusters, mesh.positions(), centre, {0.0f, 0.0f, 1.0f}, 100.0f, o), 1u);
      const float dt = 0.5f / float(steps);
      for (int s = 0; s < steps; ++s) step_soft_body(state, dt, o);
      const double t = double(dt) * steps;
      const double expected = k.x(t) * (1.0 - 0.0);  // the poke is at the centre: falloff 1
      EXPECT_NEAR(state.displacement[0].z, expected, 1e-5 + 1e-4 * std::abs(expected))
          << "c " << k.c << " steps " << steps;
      EXPECT_EQ(state.displacement[0].x, 0.0f);
    }
}

TEST(SoftbodySimulationTest, poking_while_animating_moves_vertices_relative_to_the_animated_pose_only) {
  const Cactus c = load_cactus();
  ASSERT_FALSE(c.model.animations.empty());
  const Clusters clusters = Clusters::build(*c.mesh, c.rest, ClusterOptions{0.73f});
  auto posed_at = [&](float t) {
    return posed_positions(c.model, c.node, *c.mesh, world_matrices(c.model, sample_pose(c.model, 0, t)));
  };
  const float t0 = 0.7f, dt = 1.0f / 30.0f;
  const std::vector<glm::vec3> posed0 = posed_at(t0);
  const std::uint32_t target = nearest_vertex(c.rest, {1.2f, 6.0f, 0.0f});
  const glm::vec3 impulse(-3.0f, 0.0f, 1.0f);
  SoftBodyState animated = make_soft_body(clusters);
  ASSERT_GT(poke(animated, clusters, posed0, posed0[target], impulse, 1.2f), 0u);
  SoftBodyState still = animated;  // the same poke, evaluated on the rest pose

  // Vertices outside every poked particle.
  std::vector<std::uint8_t> reached(clusters.particle_slots(), 0);
  for (std::uint32_t p = 0; p < clusters.particle_slots(); ++p)
    reached[p] = glm::length(animated.velocity[p]) > 0.0f;
  std::vector<std::uint32_t> far;
  for (std::uint32_t v = 0; v < c.rest.size(); ++v) {
    bool touched = false;
    for (const Influence& in : clusters.influences(VertexId(v))) touched = touched || reached[in.particle];
    if (!touched) far.push_back(v);
  }
  ASSERT_GT(far.size(), c.rest.size() / 2);

  std::vector<glm::vec3> out_animated, out_still;
  float animation_motion = 0.0f, peak = 0.0f;
  float t = t0;
  for (int f = 0; f < 120; ++f) {
    t += dt;
    const std::vector<glm::vec3> posed = posed_at(t);
    step_soft_body(animated, dt);
    step_soft_body(still, dt);
    deformed_positions(animated, clusters, posed, out_animated);
    deformed_positions(still, clusters, c.rest, out_still);
    for (std::uint32_t v = 0; v < posed.size(); ++v) {
      animation_motion = std::max(animation_motion, glm::length(posed[v] - c.rest[v]));
      // The offset from the animated pose is the soft-body displacement, whatever the pose.
      ASSERT_NEAR(glm::length((out_animated[v] - posed[v]) - (out_still[v] - c.rest[v])), 0.0f,
                  1e-5f * c.size)
          << "vertex " << v << " frame " << f;
    }
    for (std::uint32_t v : far)
      ASSERT_EQ(out_animated[v], posed[v]) << "far vertex " << v << " left the animated pose";
    const glm::vec3 offset = out_animated[target] - posed[target];
    peak = std::max(peak, glm::length(offset));
    if (f < 5) {
      EXPECT_GT(glm::dot(offset, impulse), 0.0f) << "the poked vertex moves along the impulse";
    }
    if (f == 119) {
      for (std::uint32_t v = 0; v < posed.size(); ++v)
        ASSERT_LT(glm::length(out_animated[v] - posed[v]), 1e-4f * c.size)
            << "vertex " << v << " did not spring back";
    }
  }
  EXPECT_GT(animation_motion, 0.01f * c.size) << "the animation should move the model";
  EXPECT_GT(peak, 1e-3f * c.size);
}

TEST(SoftbodySimulationTest, drag_holds_the_grabbed_region_then_springs_back) {
  const SurfaceMesh mesh = test::make_grid(20, 20);
  const Clusters clusters = Clusters::build(mesh, ClusterOptions{0.2f});
  SoftBodyState state = make_soft_body(clusters);
  const glm::vec3 grab(0.5f, 0.5f, 0.0f), target(0.5f, 0.5f, 0.3f);
  ASSERT_GT(drag(state, clusters, mesh.positions(), grab, target, 0.4f), 0u);
  const std::uint32_t v = nearest_vertex(mesh.positions(), grab);
  std::vector<glm::vec3> out;
  for (int f = 0; f < 120; ++f) step_soft_body(state, 1.0f / 30.0f);
  deformed_positions(state, clusters, mesh.positions(), out);
  glm::vec3 expected(0.0f);
  for (const Influence& in : clusters.influences(VertexId(v)))
    expected += in.weight * state.goal[in.particle];
  EXPECT_GT(expected.z, 0.1f);
  EXPECT_NEAR(out[v].z - mesh.positions()[v].z, expected.z, 1e-4f);
  EXPECT_NEAR(out[v].x, mesh.positions()[v].x, 1e-5f);
  const glm::vec3 corner = out[0] - mesh.positions()[0];
  EXPECT_EQ(corner, glm::vec3(0.0f)) << "a corner far from the grab stays put";
  release_drag(state);
  for (int f = 0; f < 120; ++f) step_soft_body(state, 1.0f / 30.0f);
  EXPECT_LT(max_vertex_displacement(state, clusters), 1e-4f * 1.5f);
}

TEST(SoftbodySimulationTest, poke_that_misses_changes_nothing) {
  const SurfaceMesh mesh = test::make_grid(6, 6);
  const Clusters clusters = Clusters::build(mesh, ClusterOptions{0.3f});
  SoftBodyState state = make_soft_body(clusters);
  EXPECT_EQ(poke(state, clusters, mesh.positions(), {10.0f, 10.0f, 10.0f}, {1.0f, 0.0f, 0.0f}, 0.5f), 0u);
  for (const auto& v : state.velocity) EXPECT_EQ(v, glm::vec3(0.0f));
  step_soft_body(state, 1.0f / 30.0f);
  EXPECT_EQ(max_vertex_displacement(state, clusters), 0.0f);
}

TEST(SoftbodySimulationTest, rejects_bad_input) {
  const SurfaceMesh mesh = test::make_grid(6, 6);
  const Clusters clusters = Clusters::build(mesh, ClusterOptions{0.3f});
  SoftBodyState state = make_soft_body(clusters);
  const auto& pos = mesh.positions();
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  EXPECT_THROW(poke(state, clusters, pos, {0.5f, 0.5f, 0.0f}, {0, 0, 1}, 0.0f), Error);
  EXPECT_THROW(poke(state, clusters, pos, {nan, 0.5f, 0.0f}, {0, 0, 1}, 0.3f), Error);
  EXPECT_THROW(poke(state, clusters, pos, {0.5f, 0.5f, 0.0f}, {0, inf, 1}, 0.3f), Error);
  EXPECT_THROW(drag(state, clusters, pos, {0.5f, 0.5f, 0.0f}, {0, 0, 1}, -1.0f), Error);
  EXPECT_THROW(step_soft_body(state, -0.1f), Error);
  EXPECT_THROW(step_soft_body(state, nan), Error);
  EXPECT_THROW(step_soft_body(state, inf), Error);
  SoftBodyOptions bad;
  bad.mass = 0.0f;
  EXPECT_THROW(step_soft_body(state, 0.01f, bad), Error);
  bad = {};
  bad.stiffness = -1.0f;
  EXPECT_THROW(step_soft_body(state, 0.01f, bad), Error);
  bad = {};
  bad.damping = nan;
  EXPECT_THROW(step_soft_body(state, 0.01f, bad), Error);
  std::vector<glm::vec3> out;
  const std::vector<glm::vec3> short_pose(pos.begin(), pos.end() - 1);
  EXPECT_THROW(deformed_positions(state, clusters, short_pose, out), Error);
  EXPECT_THROW(posed_particle_centres(clusters, short_pose), Error);
  SoftBodyState other = make_soft_body(Clusters::build(mesh, ClusterOptions{0.1f}));
  EXPECT_THROW(deformed_positions(other, clusters, pos, out), Error);
  EXPECT_THROW(poke(other, clusters, pos, {0.5f, 0.5f, 0.0f}, {0, 0, 1}, 0.3f), Error);
  EXPECT_NO_THROW(step_soft_body(state, 0.0f));
}

}  // namespace
}  // namespace deepcut
