// SPDX-License-Identifier: MIT
// A capped cut's second cap takes its triangles from the first cap's clip, mirrored, where that
// clip was exact (caps.cpp, MirrorClip): the same cut with every polygon clipped gives the same
// mesh, and symmetric polygons, whose ears tie, are clipped.
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>

#include <gtest/gtest.h>

#include "deepcut/core/ops/cut.h"
#include "fixtures.h"
#include "ops/cut/caps.h"

namespace deepcut {
namespace {

// Two tubes side by side (two islands per cap), each ring's radius jittered so that no two ears
// tie, or (`jitter` 0) regular ones, whose symmetric ears tie (the clip is then never exact).
SurfaceMesh two_tubes(float jitter) {
  SurfaceMesh mesh = test::make_tube(40, 5, 1.0f, 2.0f);
  const SurfaceMesh other = test::make_tube(29, 4, 0.8f, 2.0f);
  const auto offset = static_cast<std::uint32_t>(mesh.vertex_count());
  for (const auto& p : other.positions()) mesh.add_vertex(p + glm::vec3(3.0f, 0.0f, 0.5f));
  other.for_each_face([&](FaceId, const Triangle& t) {
    mesh.add_face(VertexId(t[0].index + offset), VertexId(t[1].index + offset),
                  VertexId(t[2].index + offset));
  });
  std::mt19937 rng(19);
  std::uniform_real_distribution<float> scale(1.0f - jitter, 1.0f + jitter);
  for (auto& p : mesh.positions()) {
    const float cx = p.x > 1.5f ? 3.0f : 0.0f, cz = p.x > 1.5f ? 0.5f : 0.0f, s = scale(rng);
    p.x = cx + (p.x - cx) * s;
    p.z = cz + (p.z - cz) * s;
  }
  return mesh;
}

// The capped cut of `input` by `plane`, with the second cap's triangles taken from the first where
// they are the same (`mirroring`), or every polygon clipped.
std::pair<SurfaceMesh, detail::CapMirrorStats> capped_cut(const SurfaceMesh& input, const Plane& plane,
                                                          bool mirroring) {
  SurfaceMesh mesh = input;
  CutOptions options;
  options.cap = true;
  detail::set_cap_mirroring(mirroring);  // make_caps runs on this thread: the stats are this thread's
  cut_mesh(mesh, mesh.positions(), plane, options);
  detail::set_cap_mirroring(true);
  return {std::move(mesh), detail::cap_mirror_stats()};
}

TEST(CutTest, second_cap_taken_from_the_first_equals_clipping_it) {
  const SurfaceMesh jittered = two_tubes(0.08f), regular = two_tubes(0.0f);
  std::size_t mirrored = 0, clipped = 0;
  for (int k = 0; k < 12; ++k) {
    const float t = float(k) / 12.0f;
    const Plane plane{{0.1f * t, 0.3f + 1.4f * t, 0.05f},
                      {0.15f * std::sin(7.0f * t), 1.0f, 0.1f * std::cos(5.0f * t)}};
    // The regular tubes cut square across: rotationally symmetric polygons.
    const Plane across{{0.0f, 0.13f + 0.14f * float(k), 0.0f}, {0.0f, 1.0f, 0.0f}};
    for (const SurfaceMesh* input : {&jittered, &regular}) {
      const Plane& p = input == &regular ? across : plane;
      const auto [with, stats] = capped_cut(*input, p, true);
      const auto [without, none] = capped_cut(*input, p, false);
      EXPECT_EQ(none.mirrored + none.clipped, 0u);
      ASSERT_EQ(stats.mirrored + stats.clipped, 2u) << k;  // two islands per cap
      if (input == &jittered) mirrored += stats.mirrored;
      if (input == &regular) clipped += stats.clipped;
      EXPECT_EQ(with.faces(), without.faces()) << k;
      EXPECT_EQ(with.positions(), without.positions()) << k;
    }
  }
  EXPECT_GT(mirrored, 12u);  // most jittered polygons are taken from the first cap
  EXPECT_GE(clipped, 12u);   // most regular ones tie: they fall back to clipping
}

}  // namespace
}  // namespace deepcut
