// SPDX-License-Identifier: MIT
#pragma once
// Shared by the compressed-glTF fuzz targets: wraps fuzzed bytes into a .glb around a JSON
// document and reads it from memory. Bad input must end in deepcut::Error{InvalidInput};
// anything else (a crash, a sanitizer report, another exception, an allocation past
// -rss_limit_mb) is a finding.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"

namespace deepcut::fuzz {

inline std::vector<unsigned char> make_glb(std::string json, const std::vector<unsigned char>& bin) {
  while (json.size() % 4) json += ' ';
  std::vector<unsigned char> out;
  auto put32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<unsigned char>(v >> (8 * i)));
  };
  const std::size_t bin_padded = (bin.size() + 3) & ~std::size_t(3);
  put32(0x46546C67u);
  put32(2);
  put32(static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin_padded));
  put32(static_cast<std::uint32_t>(json.size()));
  put32(0x4E4F534Au);
  out.insert(out.end(), json.begin(), json.end());
  put32(static_cast<std::uint32_t>(bin_padded));
  put32(0x004E4942u);
  out.insert(out.end(), bin.begin(), bin.end());
  out.resize(out.size() + bin_padded - bin.size(), 0);
  return out;
}

// Reads `glb`; aborts on anything but success or a clean InvalidInput refusal.
inline void read_or_refuse(const std::vector<unsigned char>& glb, const char* target) {
  try {
    (void)deepcut::read_gltf_memory(glb, "fuzz.glb");
  } catch (const deepcut::Error& e) {
    if (e.code() == deepcut::ErrorCode::InvalidInput) return;
    std::fprintf(stderr, "%s: unexpected error code: %s\n", target, e.what());
    std::abort();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: exception that is not deepcut::Error: %s\n", target, e.what());
    std::abort();
  }
}

// Little-endian unsigned integer of `n` bytes at `p`.
inline std::uint32_t read_le(const std::uint8_t* p, int n) {
  std::uint32_t v = 0;
  for (int i = 0; i < n; ++i) v |= std::uint32_t(p[i]) << (8 * i);
  return v;
}

}  // namespace deepcut::fuzz
