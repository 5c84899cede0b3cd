// SPDX-License-Identifier: MIT
// Accessors through the glTF reader, on inputs built in the test: the elements it reads in place
// (packed, aligned floats and 32-bit indices) and those it must copy because the file places
// them at an odd byte offset give the same model.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "deepcut/core/io/gltf.h"
#include "gltf_morph_fixtures.h"

namespace deepcut {
namespace {

using morph_test::Tiny;
using nlohmann::json;

// A bufferView over `bytes` bytes of `data` placed at `pad` bytes past a 4-byte boundary.
int view_at(Tiny& t, const void* data, std::size_t bytes, std::size_t pad) {
  while (t.bin.size() % 4) t.bin.push_back(0);
  t.bin.insert(t.bin.end(), pad, 0);
  t.doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", t.bin.size()}, {"byteLength", bytes}});
  const auto* p = static_cast<const unsigned char*>(data);
  t.bin.insert(t.bin.end(), p, p + bytes);
  return static_cast<int>(t.doc["bufferViews"].size() - 1);
}

// A quad (two triangles) whose positions, normals, texture coordinates (floats) and 32-bit indices
// start `pad` bytes past a 4-byte boundary of the BIN chunk.
std::vector<unsigned char> quad_glb(std::size_t pad) {
  Tiny t;
  t.doc["asset"] = {{"version", "2.0"}};
  t.doc["scene"] = 0;
  t.doc["scenes"] = json::array({json{{"nodes", {0}}}});
  t.doc["nodes"] = json::array({json{{"mesh", 0}}});
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const std::vector<float> nrm = {0, 0, 1, 0, 0.6f, 0.8f, 0, 0, 1, 0.6f, 0, 0.8f};
  const std::vector<float> uv = {0, 0, 1, 0, 1, 1, 0.25f, 0.75f};
  const std::vector<std::uint32_t> idx = {0, 1, 2, 0, 2, 3};
  auto accessor = [&](const void* data, std::size_t bytes, int type, std::size_t count, const char* shape) {
    return t.accessor({{"bufferView", view_at(t, data, bytes, pad)}, {"componentType", type}, {"count", count}, {"type", shape}});
  };
  const int p = accessor(pos.data(), 48, 5126, 4, "VEC3");
  t.doc["accessors"][std::size_t(p)]["min"] = {0, 0, 0};
  t.doc["accessors"][std::size_t(p)]["max"] = {1, 1, 0};
  const int n = accessor(nrm.data(), 48, 5126, 4, "VEC3");
  const int u = accessor(uv.data(), 32, 5126, 4, "VEC2");
  const int i = accessor(idx.data(), 24, 5125, 6, "SCALAR");
  t.doc["meshes"] = json::array({json{{"primitives", json::array({json{
                        {"attributes", {{"POSITION", p}, {"NORMAL", n}, {"TEXCOORD_0", u}}}, {"indices", i}, {"mode", 4}}})}}});
  return t.glb();
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace

TEST(GltfAccessorTest, floats_and_indices_at_an_odd_byte_offset_read_as_aligned_ones_do) {
  const Model aligned = read_gltf_memory(quad_glb(0), "aligned.glb");
  for (const std::size_t pad : {1u, 2u, 3u}) {
    SCOPED_TRACE(pad);
    const Model odd = read_gltf_memory(quad_glb(pad), "odd.glb");
    ASSERT_EQ(odd.meshes.size(), 1u);
    ASSERT_EQ(odd.meshes[0].primitives.size(), 1u);
    const SurfaceMesh& a = aligned.meshes[0].primitives[0].mesh;
    const SurfaceMesh& b = odd.meshes[0].primitives[0].mesh;
    EXPECT_EQ(b.vertex_count(), 4u);
    EXPECT_EQ(b.face_count(), 2u);
    EXPECT_TRUE(same_bytes(a.positions(), b.positions()));
    EXPECT_TRUE(same_bytes(a.faces(), b.faces()));
    EXPECT_TRUE(same_bytes(a.corner_attrs().get<glm::vec3>(attr::kNormal).data(),
                           b.corner_attrs().get<glm::vec3>(attr::kNormal).data()));
    EXPECT_TRUE(same_bytes(a.corner_attrs().get<glm::vec2>(attr::kUv0).data(),
                           b.corner_attrs().get<glm::vec2>(attr::kUv0).data()));
    EXPECT_EQ(a.corner_attrs().names(), b.corner_attrs().names());
    EXPECT_EQ(aligned.import_problems.size(), odd.import_problems.size());
  }
  // The values are the file's: the quad's third vertex and its normal.
  const SurfaceMesh& a = aligned.meshes[0].primitives[0].mesh;
  EXPECT_EQ(a.positions()[2], glm::vec3(1, 1, 0));
  const glm::vec3 normal = a.corner_attrs().get<glm::vec3>(attr::kNormal).data()[1];
  EXPECT_NEAR(normal.y, 0.6f, 1e-6f);
  EXPECT_NEAR(normal.z, 0.8f, 1e-6f);
}

}  // namespace deepcut
