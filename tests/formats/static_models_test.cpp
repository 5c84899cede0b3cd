// SPDX-License-Identifier: MIT
// The scanned static meshes (test::static_models(): spot, plus the local-only Stanford bunny,
// horse, fertility, ... when present) through cut, tear and drill: holes, unreferenced vertices,
// high genus and ~100K triangles. After every operation of a seeded random sequence the mesh
// must stay valid (weights normalised, indices in range), the incremental adjacency must equal a
// rebuild, and nothing may become non-manifold that was manifold. Failures print seed and step.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <random>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/cut.h"
#include "deepcut/core/ops/drill.h"
#include "deepcut/core/ops/tear.h"
#include "deepcut/core/spatial_index.h"
#include "deepcut/core/validate.h"
#include "deepcut/plugins/formats.h"
#include "fixtures.h"
#include "tools.h"

namespace deepcut {
namespace {

glm::vec3 random_direction(std::mt19937& rng) {
  std::normal_distribution<float> g(0.0f, 1.0f);
  for (;;) {
    const glm::vec3 d(g(rng), g(rng), g(rng));
    const float len = glm::length(d);
    if (len > 1e-3f) return d / len;
  }
}

glm::vec3 random_point(const BoundingBox& box, std::mt19937& rng, float margin = 0.0f) {
  std::uniform_real_distribution<float> u(margin, 1.0f - margin);
  return box.min + glm::vec3(u(rng), u(rng), u(rng)) * (box.max - box.min);
}

// A live face picked uniformly, its centroid and unit normal.
std::pair<glm::vec3, glm::vec3> random_surface_point(const SurfaceMesh& mesh, std::mt19937& rng) {
  std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(mesh.face_slots() - 1));
  for (;;) {
    const FaceId f(pick(rng));
    if (mesh.is_deleted(f)) continue;
    const Triangle& t = mesh.face(f);
    const glm::vec3 a = mesh.position(t[0]), b = mesh.position(t[1]), c = mesh.position(t[2]);
    const glm::vec3 n = glm::cross(b - a, c - a);
    if (glm::length(n) < 1e-12f) continue;
    return {(a + b + c) / 3.0f, glm::normalize(n)};
  }
}

struct SequenceCounts {
  std::size_t cuts = 0, tears = 0, drills = 0, changed = 0;
};

// `steps` random operations (cut, tear, drill in turn) on `mesh`, checking after each one.
void run_sequence(SurfaceMesh& mesh, unsigned seed, int steps, SequenceCounts& counts) {
  std::mt19937 rng(seed);
  Adjacency adj = Adjacency::build(mesh);
  const bool manifold_before = adj.nonmanifold_edges().empty();
  const BoundingBox box = mesh.bounds();
  const float size = box.diagonal();
  for (int step = 0; step < steps; ++step) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " step " + std::to_string(step));
    const std::vector<glm::vec3> posed = mesh.positions();
    EditLog log;
    OpStatus status = OpStatus::Ok;
    switch (step % 3) {
      case 0: {
        CutOptions options;
        options.cap = step % 2 == 1;
        const Plane plane{random_point(box, rng, 0.2f), random_direction(rng)};
        CutResult r = cut_mesh(mesh, posed, plane, options);
        status = r.status;
        log = std::move(r.log);
        ++counts.cuts;
        break;
      }
      case 1: {
        const auto [p, n] = random_surface_point(mesh, rng);
        glm::vec3 along = glm::cross(n, random_direction(rng));
        if (glm::length(along) < 1e-3f) along = glm::cross(n, glm::vec3(1, 0, 0));
        along = glm::normalize(along) * (0.04f * size);
        const glm::vec3 depth = n * (0.03f * size);
        const Blade start{p - along + depth, p - along - depth};
        const Blade end{p + along + depth, p + along - depth};
        PosedMesh at_rest = PosedMesh::at_positions(mesh);
        TearResult r = tear_mesh(mesh, at_rest, start, end);
        status = r.status;
        log = std::move(r.log);
        ++counts.tears;
        break;
      }
      default: {
        const auto [p, n] = random_surface_point(mesh, rng);
        const glm::vec3 axis = glm::normalize(n + 0.3f * random_direction(rng));
        Cylinder c;
        c.a = p + axis * (0.1f * size);
        c.b = p - axis * (0.1f * size);
        c.radius = 0.02f * size;
        DrillOptions options;
        options.wall = step % 2 == 0;
        DrillResult r = drill_mesh(mesh, PosedMesh::at_positions(mesh, posed), c, options);
        status = r.status;
        log = std::move(r.log);
        ++counts.drills;
        break;
      }
    }
    counts.changed += status == OpStatus::Ok;
    adj.apply(log);
    test::expect_valid(mesh, 1);
    test::expect_adjacency_matches_rebuild(adj, mesh);
    if (manifold_before) {
      EXPECT_TRUE(adj.nonmanifold_edges().empty()) << "a manifold input stays manifold";
    }
    if (::testing::Test::HasFailure()) {
      std::printf("static model sequence failed: seed %u step %d\n", seed, step);
      return;
    }
  }
}

}  // namespace

TEST(StaticModelsTest, every_static_model_loads_unrigged_and_exports_validator_clean) {
  const std::string dir = test::temp_dir("static-models");
  for (const std::string& path : test::static_models()) {
    SCOPED_TRACE(path);
    const Model model = plugins::read_model(path);
    ASSERT_EQ(model.skins.size(), 1u);
    ASSERT_EQ(model.skins[0].joints.size(), 1u);
    const SurfaceMesh& mesh = model.meshes.at(0).primitives.at(0).mesh;
    test::expect_valid(mesh, 1);
    const ModelStats stats = compute_stats(model);
    std::printf("%s: %zu vertices (%zu in the file), %zu triangles, %zu boundary edges, %zu non-manifold edges, "
                "%zu components, %zu notes\n",
                path.c_str(), stats.welded_vertices, stats.gltf_vertices, stats.triangles, stats.boundary_edges,
                stats.nonmanifold_edges, stats.components, model.import_problems.size());
    const std::string out = dir + "/" + model.meshes[0].name + ".glb";
    write_gltf(model, out);
    const auto v = test::validate_gltf(out);
    EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
    EXPECT_EQ(compute_stats(read_gltf(out)).triangles, stats.triangles);
  }
  std::filesystem::remove_all(dir);
}

TEST(StaticModelsTest, random_cut_tear_drill_sequences_keep_the_invariants) {
  const unsigned seed = 20261122;
  for (const std::string& path : test::static_models()) {
    SCOPED_TRACE(path);
    const Model model = plugins::read_model(path);
    SurfaceMesh mesh = model.meshes.at(0).primitives.at(0).mesh;
    SequenceCounts counts;
    run_sequence(mesh, seed, 12, counts);
    if (::testing::Test::HasFailure()) return;
    std::printf("%s: %zu cuts, %zu tears, %zu drills, %zu changed the mesh; now %zu triangles\n", path.c_str(),
                counts.cuts, counts.tears, counts.drills, counts.changed, mesh.face_count());
    EXPECT_GT(counts.changed, 6u) << "most operations aimed at the surface change it";
  }
}

TEST(StaticModelsTest, model_operations_on_spot_export_rigged_and_validator_clean) {
  const std::string dir = test::temp_dir("static-ops");
  const Model original = plugins::read_model(std::string(DEEPCUT_ASSETS_DIR) + "/models/spot/spot.obj");
  const BoundingBox box = original.meshes[0].primitives[0].mesh.bounds();
  const glm::vec3 c = 0.5f * (box.min + box.max);
  Model model = original;
  CutOptions cap;
  cap.cap = true;
  ASSERT_EQ(cut_model(model, Plane{c, {1, 0.2f, 0}}, cap).status, OpStatus::Ok);
  Cylinder drill;
  drill.a = c + glm::vec3(0, 0, box.max.z - c.z + 0.1f);
  drill.b = c - glm::vec3(0, 0, c.z - box.min.z + 0.1f);
  drill.radius = 0.05f * box.diagonal();
  DrillOptions wall;
  wall.wall = true;
  ASSERT_EQ(drill_model(model, drill, wall).status, OpStatus::Ok);
  for (const Mesh& m : model.meshes)
    for (const Primitive& p : m.primitives) test::expect_valid(p.mesh, 1);
  const std::string out = dir + "/spot-cut-drilled.glb";
  write_gltf(model, out);
  const auto v = test::validate_gltf(out);
  EXPECT_EQ(v.exit_code, 0) << v.out << v.err;
  const Model back = read_gltf(out);
  EXPECT_EQ(back.skins.size(), 1u);
  EXPECT_GE(back.meshes.size(), 2u) << "the cut made pieces";
  std::filesystem::remove_all(dir);
}

}  // namespace deepcut
