// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/softbody/clustering.h"
#include "fixtures.h"
#include "softbody/clustering_detail.h"
#include "thread_count.h"

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

// ---- Thread counts. The build on 1, 2, 3, 8 and 16 threads (the seeds' rescans cut into pieces,
// the member lists filed per chunk, the split of particles into parts, the rows fixed after a
// split by a mark per vertex or by sorted lists) and apply on 1 and 8 must give the same clusters.

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

// Builds on 1, 2, 3, 8 and 16 threads: the clusters are valid and the same.
void expect_same_on_every_thread_count(const SurfaceMesh& mesh, const ClusterOptions& options) {
  Clusters one;
  {
    ThreadCount guard(1);
    one = Clusters::build(mesh, options);
  }
  const std::vector<std::string> problems = check_clusters(one, mesh, mesh.positions());
  EXPECT_TRUE(problems.empty()) << problems.front();
  for (const std::size_t threads : {2u, 3u, 8u, 16u}) {
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

TEST(SoftbodyClusterThreadsTest,
     more_particles_than_vertices_per_chunk_list_members_alike_on_every_thread_count) {
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

// A hash of every particle's members and every vertex's influences (particle and weight bits).
std::uint64_t fingerprint(const Clusters& c, std::size_t vertices) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the little-endian bytes
  auto mix = [&](std::uint32_t x) {
    for (int i = 0; i < 4; ++i) {
      h ^= (x >> (8 * i)) & 0xffu;
      h *= 1099511628211ull;
    }
  };
  mix(static_cast<std::uint32_t>(c.particle_slots()));
  for (std::uint32_t p = 0; p < c.particle_slots(); ++p) {
    mix(static_cast<std::uint32_t>(c.members(p).size()));
    for (const std::uint32_t v : c.members(p)) mix(v);
  }
  for (std::uint32_t v = 0; v < vertices; ++v) {
    const InfluenceRange r = c.influences(VertexId(v));
    mix(static_cast<std::uint32_t>(r.end() - r.begin()));
    for (const Influence* x = r.begin(); x != r.end(); ++x) {
      std::uint32_t bits;
      std::memcpy(&bits, &x->weight, sizeof bits);
      mix(x->particle);
      mix(bits);
    }
  }
  return h;
}

SurfaceMesh small_cactus() {
  CactusOptions co;
  co.target_triangles = 20000;
  return make_cactus(co).meshes.at(0).primitives.at(0).mesh;
}

float largest_extent(const SurfaceMesh& mesh) {
  const BoundingBox box = mesh.bounds();
  const glm::vec3 ext = box.max - box.min;
  return std::max({ext.x, ext.y, ext.z});
}

TEST(SoftbodyClusterThreadsTest, small_cactus_clusters_match_the_recorded_fingerprint) {
  // Recorded from a0c62fd's clustering (before the build was spread over the pool): any change
  // of members, influences or weights fails here, on every thread count.
  const SurfaceMesh mesh = small_cactus();
  const float extent = largest_extent(mesh);
  struct Golden {
    float radius;  // times the extent
    std::size_t particles;
    std::uint64_t hash;
  };
  const Golden golden[] = {{0.03f, 1205, 0x460ad992c2aedfdfull},
                           {0.1f, 125, 0x0741274514d1cfa3ull},
                           {0.3f, 13, 0xaeec0cd95c111443ull}};
  for (const Golden& g : golden)
    for (const std::size_t threads : {1u, 2u, 3u, 8u, 16u}) {
      SCOPED_TRACE("radius " + std::to_string(g.radius) + ", threads " + std::to_string(threads));
      ThreadCount guard(threads);
      const Clusters c = Clusters::build(mesh, ClusterOptions{g.radius * extent});
      EXPECT_EQ(c.particle_count(), g.particles);
      EXPECT_EQ(fingerprint(c, mesh.vertex_count()), g.hash);
    }
}

TEST(SoftbodyClusterThreadsTest, apply_gives_copies_the_same_clusters_on_1_and_8_threads) {
  // One build, copied; one cut's log applied to each copy on its own thread count.
  SurfaceMesh mesh = small_cactus();
  const float extent = largest_extent(mesh);
  for (const float radius : {0.03f, 0.1f}) {
    SCOPED_TRACE("radius " + std::to_string(radius));
    SurfaceMesh cut_model = mesh;
    Clusters one;
    {
      ThreadCount guard(1);
      one = Clusters::build(cut_model, ClusterOptions{radius * extent});
    }
    Clusters eight = one;
    const BoundingBox box = cut_model.bounds();
    const Plane plane{0.5f * (box.min + box.max), glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f))};
    const CutResult cut = cut_mesh(cut_model, cut_model.positions(), plane);
    ASSERT_EQ(cut.status, OpStatus::Ok);
    {
      ThreadCount guard(1);
      one.apply(cut_model, cut.log);
    }
    {
      ThreadCount guard(8);
      eight.apply(cut_model, cut.log);
    }
    for (const Clusters* c : {&one, &eight}) {
      const std::vector<std::string> problems = check_clusters(*c, cut_model, cut_model.positions());
      EXPECT_TRUE(problems.empty()) << problems.front();
    }
    expect_same_clusters(one, eight, cut_model.vertex_count());
  }
}

}  // namespace
}  // namespace deepcut
