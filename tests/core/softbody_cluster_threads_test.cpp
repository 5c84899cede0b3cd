// SPDX-License-Identifier: MIT
// The clustering's build on 1, 2 and 4 threads: the seeds' rescans cut into pieces, the member
// lists filed per chunk, the split of particles into parts (grouped per root without sorting when
// a particle has few parts), and the rows fixed after a split (a mark per vertex when parts hold
// many vertices, sorted lists when few) must give the same clusters whatever the thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/softbody/clustering.h"
#include "fixtures.h"
#include "softbody/clustering_detail.h"
#include "thread_count.h"

namespace deepcut {
namespace {

using test::ThreadCount;

// The reference for parts_by_group: `by_root` (union-find root, vertex) for every member, sorted
// into ranges of one root; the largest range (the first in root order on ties) is the main part,
// the others the minors in root order, each sorted by vertex.
clustering_detail::Parts parts_by_root(std::vector<std::pair<std::uint32_t, std::uint32_t>>& by_root) {
  std::sort(by_root.begin(), by_root.end());
  std::size_t best_begin = 0, best_size = 0;
  for (std::size_t i = 0; i < by_root.size();) {
    std::size_t j = i;
    while (j < by_root.size() && by_root[j].first == by_root[i].first) ++j;
    if (j - i > best_size) best_begin = i, best_size = j - i;
    i = j;
  }
  clustering_detail::Parts parts;
  for (std::size_t i = 0; i < by_root.size();) {
    std::size_t j = i;
    while (j < by_root.size() && by_root[j].first == by_root[i].first) ++j;
    std::vector<std::uint32_t>& out = i == best_begin ? parts.main : parts.minors.emplace_back();
    for (std::size_t k = i; k < j; ++k) out.push_back(by_root[k].second);
    std::sort(out.begin(), out.end());
    i = j;
  }
  return parts;
}

// Every particle's members, seed and rest centre, and every vertex's influences, bit for bit.
void expect_same_clusters(const Clusters& a, const Clusters& b, std::size_t vertices) {
  ASSERT_EQ(a.particle_slots(), b.particle_slots());
  for (std::uint32_t p = 0; p < a.particle_slots(); ++p) {
    ASSERT_EQ(a.members(p), b.members(p)) << "particle " << p;
    ASSERT_EQ(a.seed(p), b.seed(p)) << "particle " << p;
    ASSERT_EQ(a.rest_centre(p), b.rest_centre(p)) << "particle " << p;
  }
  for (std::uint32_t v = 0; v < vertices; ++v) {
    const InfluenceRange ra = a.influences(VertexId(v)), rb = b.influences(VertexId(v));
    ASSERT_EQ(ra.end() - ra.begin(), rb.end() - rb.begin()) << "vertex " << v;
    for (const Influence *x = ra.begin(), *y = rb.begin(); x != ra.end(); ++x, ++y) {
      ASSERT_EQ(x->particle, y->particle) << "vertex " << v;
      ASSERT_EQ(std::memcmp(&x->weight, &y->weight, sizeof(float)), 0) << "vertex " << v;
    }
  }
}

// Builds on 1, 2 and 4 threads: the clusters are valid and the same.
void expect_same_on_every_thread_count(const SurfaceMesh& mesh, const ClusterOptions& options) {
  Clusters one;
  {
    ThreadCount guard(1);
    one = Clusters::build(mesh, options);
  }
  const std::vector<std::string> problems = check_clusters(one, mesh, mesh.positions());
  EXPECT_TRUE(problems.empty()) << problems.front();
  for (const std::size_t threads : {2u, 4u}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    ThreadCount guard(threads);
    expect_same_clusters(one, Clusters::build(mesh, options), mesh.vertex_count());
  }
}

// `nx` x `ny` separate triangles (islands) `gap` apart in the plane z = 0, each `size` wide.
SurfaceMesh islands(int nx, int ny, float gap, float size) {
  SurfaceMesh mesh;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const glm::vec3 o(x * gap, y * gap, 0.0f);
      const VertexId a = mesh.add_vertex(o);
      const VertexId b = mesh.add_vertex(o + glm::vec3(size, 0.0f, 0.0f));
      const VertexId c = mesh.add_vertex(o + glm::vec3(0.0f, size, 0.0f));
      mesh.add_face(a, b, c);
    }
  return mesh;
}

TEST(SoftbodyClusterThreadsTest, parts_by_group_equal_parts_by_root) {
  using clustering_detail::Parts;
  std::mt19937 rng(7);
  clustering_detail::PartsScratch scratch;
  for (int round = 0; round < 400; ++round) {
    // Ascending members, each given one of `k` roots: up to 16 parts (the linear search) and
    // more (the sorted list), scratch reused from round to round.
    const std::size_t n = 1 + rng() % 300, k = 1 + rng() % 40;
    std::vector<std::uint32_t> roots_of_parts(k), m(n), root(n);
    for (auto& r : roots_of_parts) r = rng() % 100000;
    std::uint32_t v = rng() % 10;
    for (std::size_t i = 0; i < n; ++i) {
      m[i] = v += 1 + rng() % 5;
      // Runs of one root, as members near each other tend to share one.
      root[i] = i > 0 && rng() % 4 ? root[i - 1] : roots_of_parts[rng() % k];
    }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> by_root;
    for (std::size_t i = 0; i < n; ++i) by_root.emplace_back(root[i], m[i]);
    const Parts expected = parts_by_root(by_root);
    const Parts got = clustering_detail::parts_by_group(m, root, scratch);
    SCOPED_TRACE("round " + std::to_string(round));
    EXPECT_EQ(got.main, expected.main);
    EXPECT_EQ(got.minors, expected.minors);
  }
}

TEST(SoftbodyClusterThreadsTest, many_islands_per_particle_split_alike_on_every_thread_count) {
  // 40 x 40 islands 0.1 apart: a ball of radius 0.5 holds about 80 of them (more parts than
  // parts_by_group takes), one of 0.15 a few (grouped without sorting); every part but the largest
  // leaves its particle, most vertices lie in a split-off part (rows fixed by mark).
  const SurfaceMesh mesh = islands(40, 40, 0.1f, 0.04f);
  for (const float radius : {0.5f, 0.15f}) {
    SCOPED_TRACE("radius " + std::to_string(radius));
    expect_same_on_every_thread_count(mesh, ClusterOptions{radius});
  }
}

TEST(SoftbodyClusterThreadsTest, more_particles_than_vertices_per_chunk_list_members_alike_on_every_thread_count) {
  // 67500 vertices (three chunks of the member lists) and a radius under an island's size: tens
  // of thousands of particles, so the lists are filed through the packed copy, not per chunk.
  const SurfaceMesh mesh = islands(150, 150, 0.1f, 0.04f);
  Clusters one;
  {
    ThreadCount guard(1);
    one = Clusters::build(mesh, ClusterOptions{0.015f});
  }
  ASSERT_GT(one.particle_count() * 3, mesh.vertex_count());
  expect_same_on_every_thread_count(mesh, ClusterOptions{0.015f});
}

TEST(SoftbodyClusterThreadsTest, one_small_island_beside_a_sheet_splits_alike_on_every_thread_count) {
  // A sheet and one small triangle just off it: few vertices leave their particles (rows fixed
  // from sorted lists).
  SurfaceMesh mesh = test::make_grid(60, 60);
  const BoundingBox box = mesh.bounds();
  const glm::vec3 o = box.max + glm::vec3(0.01f, 0.01f, 0.0f);
  const VertexId a = mesh.add_vertex(o);
  const VertexId b = mesh.add_vertex(o + glm::vec3(0.01f, 0.0f, 0.0f));
  const VertexId c = mesh.add_vertex(o + glm::vec3(0.0f, 0.01f, 0.0f));
  mesh.add_face(a, b, c);
  const float extent = std::max(box.max.x - box.min.x, box.max.y - box.min.y);
  expect_same_on_every_thread_count(mesh, ClusterOptions{0.2f * extent});
}

TEST(SoftbodyClusterThreadsTest, coarse_grid_of_large_cells_builds_alike_on_every_thread_count) {
  // A radius large against the model: few grid cells of thousands of points each, whose rescans
  // are cut into pieces.
  CactusOptions co;
  co.target_triangles = 200000;
  const SurfaceMesh mesh = make_cactus(co).meshes.at(0).primitives.at(0).mesh;
  const BoundingBox box = mesh.bounds();
  const glm::vec3 ext = box.max - box.min;
  expect_same_on_every_thread_count(mesh, ClusterOptions{0.25f * std::max({ext.x, ext.y, ext.z})});
}

TEST(SoftbodyClusterThreadsTest, degenerate_face_joins_its_two_distinct_corners) {
  // Two islands under one ball: two particles, unless a face with a repeated corner links them
  // (the edge between its repeated corners is skipped, its other edges link the islands).
  SurfaceMesh apart = islands(2, 1, 0.1f, 0.04f);
  EXPECT_EQ(Clusters::build(apart, ClusterOptions{1.0f}).particle_count(), 2u);
  SurfaceMesh linked = apart;
  linked.add_face(VertexId(1), VertexId(1), VertexId(3));
  EXPECT_EQ(Clusters::build(linked, ClusterOptions{1.0f}).particle_count(), 1u);
  expect_same_on_every_thread_count(linked, ClusterOptions{1.0f});
  // A face of one vertex links nothing.
  SurfaceMesh point = apart;
  point.add_face(VertexId(1), VertexId(1), VertexId(1));
  EXPECT_EQ(Clusters::build(point, ClusterOptions{1.0f}).particle_count(), 2u);
}

TEST(SoftbodyClusterThreadsTest, empty_and_single_triangle_meshes_build_on_every_thread_count) {
  SurfaceMesh empty;
  empty.add_vertex({0.0f, 0.0f, 0.0f});
  expect_same_on_every_thread_count(empty, ClusterOptions{1.0f});
  expect_same_on_every_thread_count(islands(1, 1, 1.0f, 0.5f), ClusterOptions{1.0f});
}

}  // namespace
}  // namespace deepcut
