// SPDX-License-Identifier: MIT
// The clustering's seed sampling against a brute-force farthest-point sampling: the grid sampler
// skips cells that cannot change and rescans the others on several threads, and must still pick
// exactly the seeds, in the same order, that scanning every point for every seed picks.
#include <gtest/gtest.h>

#include "thread_count.h"

#include <cmath>
#include <limits>
#include <string>

#include "deepcut/core/errors.h"
#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/softbody/clustering.h"

namespace deepcut {
namespace {

using test::ThreadCount;

float dist2(const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 d = a - b;
  return glm::dot(d, d);
}

// Farthest-point sampling by scanning every live vertex for every seed: the first seed is the
// vertex farthest from the box centre, each next one the vertex farthest from the seeds so far,
// ties to the smaller index, until every vertex lies within `cover` of a seed.
std::vector<std::uint32_t> brute_force_seeds(const SurfaceMesh& mesh, float cover) {
  const std::vector<glm::vec3>& rest = mesh.positions();
  std::vector<std::uint8_t> live(mesh.vertex_count(), 0);
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (const VertexId v : t) live[v.index] = 1;
  });
  std::vector<std::uint32_t> ids;
  BoundingBox box;
  for (std::uint32_t v = 0; v < live.size(); ++v)
    if (live[v]) ids.push_back(v), box.add(rest[v]);
  const glm::vec3 centre = 0.5f * (box.min + box.max);
  std::uint32_t seed = ids[0];
  float best = -1.0f;
  for (std::uint32_t v : ids)
    if (dist2(rest[v], centre) > best) best = dist2(rest[v], centre), seed = v;
  std::vector<float> d2(rest.size(), std::numeric_limits<float>::infinity());
  std::vector<std::uint32_t> seeds;
  for (;;) {
    seeds.push_back(seed);
    best = -1.0f;
    for (std::uint32_t v : ids) {
      d2[v] = std::min(d2[v], dist2(rest[v], rest[seeds.back()]));
      if (d2[v] > best) best = d2[v], seed = v;
    }
    if (best <= cover * cover) return seeds;
  }
}

SurfaceMesh cactus_mesh(std::size_t triangles) {
  CactusOptions co;
  co.target_triangles = triangles;
  return make_cactus(co).meshes.at(0).primitives.at(0).mesh;
}

TEST(SoftbodyClusterSeedsTest, seeds_equal_brute_force_sampling_for_every_thread_count) {
  // About 100k vertices: the first seeds reach enough points to be rescanned in parallel.
  const SurfaceMesh mesh = cactus_mesh(200000);
  ClusterOptions options;
  options.radius = 0.2f;
  const std::vector<std::uint32_t> expected = brute_force_seeds(mesh, options.radius * options.cover_fraction);
  ASSERT_GT(expected.size(), 50u);
  for (const std::size_t threads : {1u, 2u, 8u}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    ThreadCount guard(threads);
    const Clusters c = Clusters::build(mesh, options);
    ASSERT_GE(c.particle_slots(), expected.size());
    for (std::size_t p = 0; p < expected.size(); ++p)
      ASSERT_EQ(c.seed(static_cast<std::uint32_t>(p)), mesh.positions()[expected[p]]) << "particle " << p;
    // Particles past the sampled ones are parts split off a sampled particle: the same seed.
    for (std::size_t p = expected.size(); p < c.particle_slots(); ++p) {
      bool split_off = false;
      for (std::size_t q = 0; q < expected.size() && !split_off; ++q)
        split_off = c.seed(static_cast<std::uint32_t>(p)) == c.seed(static_cast<std::uint32_t>(q));
      EXPECT_TRUE(split_off) << "particle " << p;
    }
  }
}

TEST(SoftbodyClusterSeedsTest, non_finite_vertex_reported_is_the_smallest_for_every_thread_count) {
  const SurfaceMesh mesh = cactus_mesh(200000);
  std::vector<glm::vec3> rest = mesh.positions();
  rest[90000].x = std::numeric_limits<float>::quiet_NaN();
  rest[40000].y = std::numeric_limits<float>::infinity();
  ClusterOptions options;
  options.radius = 0.2f;
  for (const std::size_t threads : {1u, 8u}) {
    ThreadCount guard(threads);
    try {
      Clusters::build(mesh, rest, options);
      FAIL() << "no error with " << threads << " threads";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("vertex 40000 "), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace deepcut
