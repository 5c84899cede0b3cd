// SPDX-License-Identifier: MIT
// The whole-mesh passes give the same bytes whatever the thread count: read and weld, the weld
// on its own, export, the spatial index build and the clustering, each run with 1, 2, 3 and 8
// threads on a cactus large enough to span many parallel chunks.
#include <gtest/gtest.h>

#include "thread_count.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/softbody/clustering.h"
#include "deepcut/core/spatial_index.h"
#include "deepcut/core/weld.h"

namespace deepcut {
namespace {

using test::ThreadCount;

std::vector<unsigned char> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void append(std::vector<unsigned char>& out, const void* data, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  out.insert(out.end(), p, p + bytes);
}

// Every byte of a mesh: faces, deleted flags and every attribute array.
std::vector<unsigned char> mesh_bytes(const SurfaceMesh& mesh) {
  std::vector<unsigned char> out;
  append(out, mesh.faces().data(), mesh.faces().size() * sizeof(Triangle));
  for (const AttributeSet* set : {&mesh.vertex_attrs(), &mesh.corner_attrs(), &mesh.face_attrs()})
    for (const auto& name : set->names()) {
      const AttributeArrayBase* a = set->base(name);
      append(out, name.data(), name.size());
      if (a->size() > 0) append(out, a->element_data(0), a->size() * a->element_bytes());
    }
  return out;
}

std::vector<unsigned char> model_bytes(const Model& model) {
  std::vector<unsigned char> out;
  for (const auto& mesh : model.meshes)
    for (const auto& prim : mesh.primitives) {
      const auto b = mesh_bytes(prim.mesh);
      out.insert(out.end(), b.begin(), b.end());
    }
  return out;
}

std::vector<unsigned char> cluster_bytes(const Clusters& c, std::size_t vertices) {
  std::vector<unsigned char> out;
  for (std::uint32_t v = 0; v < vertices; ++v)
    for (const Influence& in : c.influences(VertexId(v))) append(out, &in, sizeof(in));
  for (std::uint32_t p = 0; p < c.particle_slots(); ++p) {
    append(out, c.members(p).data(), c.members(p).size() * sizeof(std::uint32_t));
    append(out, &c.rest_centre(p), sizeof(glm::vec3));
  }
  return out;
}

// What each pass made with one thread count.
struct Outputs {
  std::vector<unsigned char> read, weld, exported, clusters;
  std::uint64_t grid = 0;
};

Outputs run_passes(const std::string& glb, const std::string& out_path, std::size_t threads) {
  ThreadCount guard(threads);
  Outputs o;
  const Model model = read_gltf(glb);
  o.read = model_bytes(model);
  ImportOptions raw;
  raw.weld = false;
  Model unwelded = read_gltf(glb, raw);
  SurfaceMesh& mesh = unwelded.meshes.at(0).primitives.at(0).mesh;
  const WeldReport report = weld(mesh, {WeldKey::PositionAndSkin});
  o.weld = mesh_bytes(mesh);
  append(o.weld, &report, sizeof(report));
  write_gltf(model, out_path);
  o.exported = file_bytes(out_path);
  const SurfaceMesh& welded = model.meshes.at(0).primitives.at(0).mesh;
  o.grid = TriangleGrid::build(welded, welded.positions()).layout_hash();
  ClusterOptions options;
  options.radius = 0.35f;
  o.clusters = cluster_bytes(Clusters::build(welded, welded.positions(), options), welded.vertex_count());
  return o;
}

TEST(ThreadCountBytesTest, read_weld_export_index_and_clusters_are_identical_for_every_thread_count) {
  const std::string dir = testing::TempDir();
  const std::string glb = dir + "/thread_count_cactus.glb";
  CactusOptions co;
  co.target_triangles = 120000;  // about 60k vertices, 360k corners: many chunks of every pass
  write_gltf(make_cactus(co), glb);
  const Outputs one = run_passes(glb, dir + "/thread_count_out_1.glb", 1);
  ASSERT_FALSE(one.read.empty());
  ASSERT_FALSE(one.clusters.empty());
  for (const std::size_t threads : {2u, 3u, 8u}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    const Outputs many = run_passes(glb, dir + "/thread_count_out_n.glb", threads);
    EXPECT_TRUE(many.read == one.read);
    EXPECT_TRUE(many.weld == one.weld);
    EXPECT_TRUE(many.exported == one.exported);
    EXPECT_EQ(many.grid, one.grid);
    EXPECT_TRUE(many.clusters == one.clusters);
  }
}

}  // namespace
}  // namespace deepcut
