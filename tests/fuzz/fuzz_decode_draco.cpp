// SPDX-License-Identifier: MIT
// libFuzzer target: the KHR_draco_mesh_compression decoder. Input: u32 vertex count, u32 index
// count, then the Draco bytes. They become a .glb whose one primitive is Draco compressed
// (POSITION as Draco attribute 0, NORMAL as 1; accessors claiming the two counts) and is read
// from memory: clean refusals only, never a crash or an unbounded allocation.
#include <string>

#include "fuzz_compressed.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 8) return 0;
  const std::uint32_t vertices = deepcut::fuzz::read_le(data, 4), indices = deepcut::fuzz::read_le(data + 4, 4);
  const std::vector<unsigned char> payload(data + 8, data + size);
  const std::string json =
      R"({"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],)"
      R"("extensionsRequired":["KHR_draco_mesh_compression"],"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
      R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1},"indices":2,"mode":4,)"
      R"("extensions":{"KHR_draco_mesh_compression":{"bufferView":0,"attributes":{"POSITION":0,"NORMAL":1}}}}]}],)"
      R"("accessors":[{"componentType":5126,"type":"VEC3","count":)" + std::to_string(vertices) +
      R"(},{"componentType":5126,"type":"VEC3","count":)" + std::to_string(vertices) +
      R"(},{"componentType":5125,"type":"SCALAR","count":)" + std::to_string(indices) +
      R"(}],"bufferViews":[{"buffer":0,"byteLength":)" + std::to_string(payload.size()) +
      R"(}],"buffers":[{"byteLength":)" + std::to_string(payload.size()) + "}]}";
  deepcut::fuzz::read_or_refuse(deepcut::fuzz::make_glb(json, payload), "fuzz_decode_draco");
  return 0;
}
