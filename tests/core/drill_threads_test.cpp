// SPDX-License-Identifier: MIT
// The drill plans its crossed faces in parallel chunks (core/src/ops/drill/rim_faces.h) and
// makes the edits in candidate order: the result is the same whatever the thread count.
#include <gtest/gtest.h>

#include <vector>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/ops/drill.h"
#include "deepcut/core/posed_model.h"
#include "thread_count.h"

namespace deepcut {
namespace {

using test::ThreadCount;

struct Drilled {
  SurfaceMesh mesh;
  DrillResult result;
};

Drilled drill_with(std::size_t threads, const SurfaceMesh& input, const Cylinder& cyl, bool wall) {
  ThreadCount guard(threads);
  Drilled d{input, {}};
  DrillOptions options;
  options.wall = wall;
  d.result = drill_mesh(d.mesh, PosedMesh::at_positions(input), cyl, options);
  return d;
}

TEST(DrillThreadsTest, the_result_does_not_depend_on_the_thread_count) {
  CactusOptions options;
  options.target_triangles = 40000;  // a hole through the trunk crosses many planning chunks
  const Model model = make_cactus(options);
  const SurfaceMesh& input = model.meshes[0].primitives[0].mesh;
  const BoundingBox box = input.bounds();
  const glm::vec3 c = 0.5f * (box.min + box.max);
  for (const float radius : {0.03f, 0.12f})
    for (const bool wall : {false, true}) {
      const Cylinder cyl{{c.x, c.y, box.max.z + 1.0f}, {c.x - 0.1f, c.y + 0.2f, box.min.z - 1.0f},
                         radius * box.diagonal()};
      const Drilled one = drill_with(1, input, cyl, wall);
      ASSERT_EQ(one.result.status, OpStatus::Ok);
      ASSERT_GT(one.result.triangles_added, 100u);
      for (const std::size_t threads : {2u, 3u, 8u}) {
        const Drilled many = drill_with(threads, input, cyl, wall);
        SCOPED_TRACE(testing::Message() << threads << " threads, radius " << radius << ", wall " << wall);
        EXPECT_EQ(many.mesh.faces(), one.mesh.faces());
        EXPECT_EQ(many.mesh.positions(), one.mesh.positions());
        EXPECT_EQ(many.result.log.size(), one.result.log.size());
        EXPECT_EQ(many.result.added_posed, one.result.added_posed);
        ASSERT_EQ(many.result.holes.size(), one.result.holes.size());
        for (std::size_t h = 0; h < one.result.holes.size(); ++h)
          EXPECT_EQ(many.result.holes[h].rim, one.result.holes[h].rim);
        EXPECT_EQ(many.result.triangles_added, one.result.triangles_added);
        EXPECT_EQ(many.result.wall_triangles, one.result.wall_triangles);
      }
    }
}

}  // namespace
}  // namespace deepcut
