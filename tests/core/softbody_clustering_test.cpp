// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/softbody/clustering.h"
#include "fixtures.h"

namespace deepcut {
namespace {

const std::string kCactus = std::string(DEEPCUT_ASSETS_DIR) + "/cactus.glb";

std::string first_problems(const std::vector<std::string>& problems) {
  std::string out;
  for (std::size_t i = 0; i < problems.size() && i < 5; ++i) out += "\n  " + problems[i];
  return out;
}

/// Rest-pose world positions of the first primitive drawn by the first mesh node.
struct Drawn {
  Model model;
  const SurfaceMesh* mesh = nullptr;
  std::vector<glm::vec3> rest;
};

Drawn load_drawn(const std::string& path) {
  Drawn d;
  d.model = read_gltf(path);
  const auto world = world_matrices(d.model, rest_pose(d.model));
  for (std::size_t n = 0; n < d.model.nodes.size(); ++n) {
    const int m = d.model.nodes[n].mesh;
    if (m < 0) continue;
    d.mesh = &d.model.meshes[m].primitives[0].mesh;
    d.rest = posed_positions(d.model, static_cast<int>(n), *d.mesh, world);
    break;
  }
  return d;
}

TEST(SoftbodyClusteringTest, default_model_is_covered_within_radius_and_connected) {
  const Drawn d = load_drawn(kCactus);
  ASSERT_NE(d.mesh, nullptr);
  const Clusters c = Clusters::build(*d.mesh, d.rest, ClusterOptions{0.73f});
  const auto problems = check_clusters(c, *d.mesh, d.rest);
  EXPECT_TRUE(problems.empty()) << first_problems(problems);
  const ClusterStats s = cluster_stats(c, *d.mesh);
  EXPECT_EQ(s.uncovered_vertices, 0u);
  EXPECT_EQ(s.covered_vertices, 12654u);  // every welded vertex of the cactus
  EXPECT_GT(s.particles, 100u);
  EXPECT_LE(s.min_vertices, s.mean_vertices);
  EXPECT_LE(s.mean_vertices, double(s.max_vertices));
  // Overlapping particles: on average a vertex is in more than one.
  EXPECT_GT(s.memberships, s.covered_vertices);
}

TEST(SoftbodyClusteringTest, every_asset_model_is_covered) {
  for (const auto& path : test::asset_models()) {
    SCOPED_TRACE(path);
    const Drawn d = load_drawn(path);
    ASSERT_NE(d.mesh, nullptr);
    BoundingBox box;
    for (const auto& p : d.rest) box.add(p);
    for (const float fraction : {0.05f, 0.2f}) {
      const Clusters c = Clusters::build(*d.mesh, d.rest, ClusterOptions{fraction * box.diagonal()});
      const auto problems = check_clusters(c, *d.mesh, d.rest);
      EXPECT_TRUE(problems.empty()) << first_problems(problems);
      EXPECT_EQ(cluster_stats(c, *d.mesh).uncovered_vertices, 0u);
    }
  }
}

TEST(SoftbodyClusteringTest, particle_count_falls_as_radius_grows) {
  const Drawn d = load_drawn(kCactus);
  std::size_t previous = std::numeric_limits<std::size_t>::max();
  for (const float rho : {0.25f, 0.5f, 1.0f, 2.0f, 4.0f}) {
    const std::size_t count = Clusters::build(*d.mesh, d.rest, ClusterOptions{rho}).particle_count();
    EXPECT_LT(count, previous) << "rho " << rho;
    previous = count;
  }
  // Same at the sparsest cover (each vertex within rho of a seed, no more).
  previous = std::numeric_limits<std::size_t>::max();
  for (const float rho : {0.25f, 0.5f, 1.0f, 2.0f}) {
    const std::size_t count = Clusters::build(*d.mesh, d.rest, ClusterOptions{rho, 1.0f}).particle_count();
    EXPECT_LT(count, previous) << "rho " << rho;
    previous = count;
  }
}

TEST(SoftbodyClusteringTest, default_model_has_a_radius_giving_224_particles) {
  // The paper's cactus: rho 0.8 gave 224 particles. Ours is 10 units tall as well.
  const Drawn d = load_drawn(kCactus);
  std::size_t count = 0;
  const float rho = radius_for_particle_count(*d.mesh, d.rest, 224, ClusterOptions{}, &count);
  EXPECT_NEAR(double(count), 224.0, 3.0);
  EXPECT_GT(rho, 0.3f);
  EXPECT_LT(rho, 1.5f);
  const Clusters c = Clusters::build(*d.mesh, d.rest, ClusterOptions{rho});
  EXPECT_EQ(c.particle_count(), count);
  EXPECT_TRUE(check_clusters(c, *d.mesh, d.rest).empty());
  std::cout << "[ cactus  ] rho " << rho << " gives " << count << " particles\n";
}

TEST(SoftbodyClusteringTest, weights_fall_off_smoothly_and_sum_to_one) {
  const SurfaceMesh mesh = test::make_grid(30, 30);
  const float rho = 0.2f;
  const Clusters c = Clusters::build(mesh, ClusterOptions{rho});
  std::size_t multi = 0;
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    const InfluenceRange row = c.influences(VertexId(v));
    ASSERT_FALSE(row.empty());
    double sum = 0.0;
    float nearest = std::numeric_limits<float>::max();
    float nearest_weight = 0.0f;
    for (const Influence& a : row) {
      sum += a.weight;
      const float da = glm::length(mesh.positions()[v] - c.seed(a.particle));
      if (da < nearest) nearest = da, nearest_weight = a.weight;
      // Normalised weights keep the ratios of the raw falloff (1 - (d/rho)^2)^2.
      for (const Influence& b : row) {
        const float db = glm::length(mesh.positions()[v] - c.seed(b.particle));
        const float fa = std::max(std::pow(1.0f - (da / rho) * (da / rho), 2.0f), 1e-6f);
        const float fb = std::max(std::pow(1.0f - (db / rho) * (db / rho), 2.0f), 1e-6f);
        EXPECT_NEAR(a.weight / b.weight, fa / fb, 1e-3f * fa / fb);
      }
    }
    EXPECT_NEAR(sum, 1.0, 1e-5);
    // Cover fraction 0.7: the nearest seed is within 0.7 rho, so its raw weight is >= 0.26;
    // with all others at most 1, the nearest keeps a real share.
    EXPECT_LE(nearest, 0.7f * rho * 1.0001f);
    EXPECT_GT(nearest_weight, 0.26f / float(row.size()));
    multi += row.size() > 1;
  }
  EXPECT_GT(multi, mesh.vertex_count() / 2) << "particles should overlap";
}

TEST(SoftbodyClusteringTest, ball_over_two_separate_sheets_is_split) {
  // Two parallel grids 0.05 apart, clustered with rho 0.3: balls reach both sheets, but no
  // particle may hold vertices of both.
  SurfaceMesh mesh = test::make_grid(10, 10);
  const std::size_t n = mesh.vertex_count();
  std::vector<Triangle> faces;
  mesh.for_each_face([&](FaceId, const Triangle& t) { faces.push_back(t); });
  for (std::size_t v = 0; v < n; ++v) mesh.add_vertex(mesh.positions()[v] + glm::vec3(0.0f, 0.0f, 0.05f));
  const auto shift = [&](VertexId v) { return VertexId(static_cast<std::uint32_t>(v.index + n)); };
  for (const auto& t : faces) mesh.add_face(shift(t[0]), shift(t[1]), shift(t[2]));
  const Clusters c = Clusters::build(mesh, ClusterOptions{0.3f});
  const auto problems = check_clusters(c, mesh, mesh.positions());
  EXPECT_TRUE(problems.empty()) << first_problems(problems);
  for (std::uint32_t p = 0; p < c.particle_slots(); ++p) {
    const auto& m = c.members(p);
    if (m.empty()) continue;
    const bool upper = m.front() >= n;
    for (std::uint32_t v : m) EXPECT_EQ(v >= n, upper) << "particle " << p << " spans both sheets";
  }
}

TEST(SoftbodyClusteringTest, only_vertices_of_live_faces_are_clustered) {
  SurfaceMesh mesh = test::make_grid(4, 4);
  const VertexId lonely = mesh.add_vertex({5.0f, 5.0f, 5.0f});
  const Clusters c = Clusters::build(mesh, ClusterOptions{0.5f});
  EXPECT_TRUE(c.influences(lonely).empty());
  EXPECT_TRUE(check_clusters(c, mesh, mesh.positions()).empty());

  SurfaceMesh empty;
  empty.add_vertex({0.0f, 0.0f, 0.0f});
  const Clusters none = Clusters::build(empty, ClusterOptions{1.0f});
  EXPECT_EQ(none.particle_count(), 0u);
  EXPECT_EQ(cluster_stats(none, empty).uncovered_vertices, 0u);
}

TEST(SoftbodyClusteringTest, build_is_deterministic) {
  const Drawn d = load_drawn(kCactus);
  const Clusters a = Clusters::build(*d.mesh, d.rest, ClusterOptions{0.9f});
  const Clusters b = Clusters::build(*d.mesh, d.rest, ClusterOptions{0.9f});
  ASSERT_EQ(a.particle_slots(), b.particle_slots());
  for (std::uint32_t p = 0; p < a.particle_slots(); ++p) {
    EXPECT_EQ(a.members(p), b.members(p));
    EXPECT_EQ(a.seed(p), b.seed(p));
  }
}

TEST(SoftbodyClusteringTest, rejects_bad_radius_cover_and_rest_size) {
  const SurfaceMesh mesh = test::make_grid(3, 3);
  EXPECT_THROW(Clusters::build(mesh, ClusterOptions{0.0f}), Error);
  EXPECT_THROW(Clusters::build(mesh, ClusterOptions{-1.0f}), Error);
  EXPECT_THROW(Clusters::build(mesh, ClusterOptions{std::nanf("")}), Error);
  EXPECT_THROW(Clusters::build(mesh, ClusterOptions{std::numeric_limits<float>::infinity()}), Error);
  EXPECT_THROW(Clusters::build(mesh, ClusterOptions{0.5f, 0.0f}), Error);
  EXPECT_THROW(Clusters::build(mesh, ClusterOptions{0.5f, 1.5f}), Error);
  const std::vector<glm::vec3> short_rest(mesh.vertex_count() - 1);
  EXPECT_THROW(Clusters::build(mesh, short_rest, ClusterOptions{0.5f}), Error);
  std::vector<glm::vec3> nan_rest = mesh.positions();
  nan_rest[2].y = std::nanf("");
  try {
    Clusters::build(mesh, nan_rest, ClusterOptions{0.5f});
    ADD_FAILURE() << "non-finite rest position accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidInput);
    EXPECT_NE(std::string(e.what()).find("vertex 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(radius_for_particle_count(mesh, mesh.positions(), 0), Error);
}

}  // namespace
}  // namespace deepcut
