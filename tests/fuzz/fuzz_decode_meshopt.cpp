// SPDX-License-Identifier: MIT
// libFuzzer target: the EXT_meshopt_compression decoder. Input: u8 mode (ATTRIBUTES, TRIANGLES,
// INDICES), u8 filter (NONE, OCTAHEDRAL, QUATERNION, EXPONENTIAL), u16 byteStride, u32 count,
// then the compressed bytes. They become a .glb with one compressed bufferView over a fallback
// buffer, read from memory: clean refusals only, never a crash, an assert of the library or an
// unbounded allocation.
#include <string>

#include "fuzz_compressed.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 8) return 0;
  static const char* modes[] = {"ATTRIBUTES", "TRIANGLES", "INDICES"};
  static const char* filters[] = {"NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL"};
  const char* mode = modes[data[0] % 3];
  const char* filter = filters[data[1] % 4];
  const std::uint32_t stride = deepcut::fuzz::read_le(data + 2, 2), count = deepcut::fuzz::read_le(data + 4, 4);
  const std::uint64_t decoded = std::uint64_t(stride) * count;
  const std::vector<unsigned char> payload(data + 8, data + size);
  const std::string n = std::to_string(payload.size());
  const std::string json =
      R"({"asset":{"version":"2.0"},"extensionsUsed":["EXT_meshopt_compression"],)"
      R"("extensionsRequired":["EXT_meshopt_compression"],)"
      R"("bufferViews":[{"buffer":1,"byteLength":)" + std::to_string(decoded) +
      R"(,"extensions":{"EXT_meshopt_compression":{"buffer":0,"byteLength":)" + n + R"(,"byteStride":)" +
      std::to_string(stride) + R"(,"count":)" + std::to_string(count) + R"(,"mode":")" + mode + R"(","filter":")" + filter +
      R"("}}}],"buffers":[{"byteLength":)" + n + R"(},{"byteLength":)" + std::to_string(decoded) +
      R"(,"extensions":{"EXT_meshopt_compression":{"fallback":true}}}]})";
  deepcut::fuzz::read_or_refuse(deepcut::fuzz::make_glb(json, payload), "fuzz_decode_meshopt");
  return 0;
}
