// SPDX-License-Identifier: MIT
#pragma once
// Elements of several attribute arrays seen as raw rows of bytes (private to core): row i is
// element i of every array. The weld groups vertices and the glTF writer groups corners by these
// rows; both hash and compare them here, without a virtual call per element.

#include <cstdint>
#include <cstring>
#include <vector>

#include "deepcut/core/attributes.h"

namespace deepcut::detail {

class ByteRows {
 public:
  /// Adds `array` (an empty one adds nothing).
  void add(const AttributeArrayBase& array) {
    if (array.size() > 0) arrays_.push_back({static_cast<const unsigned char*>(array.element_data(0)), array.element_bytes()});
  }
  /// `h` mixed with row `row`'s bytes, 4 at a time (call `finish` on the result).
  std::uint64_t hash(std::uint32_t row, std::uint64_t h = kSeed) const {
    for (const Array& a : arrays_) {
      const unsigned char* p = a.data + std::size_t(row) * a.bytes;
      std::size_t i = 0;
      for (; i + 4 <= a.bytes; i += 4) {
        std::uint32_t word;
        std::memcpy(&word, p + i, 4);
        h = mix(h, word);
      }
      for (; i < a.bytes; ++i) h = mix(h, p[i]);
    }
    return h;
  }
  /// Whether rows `u` and `v` hold the same bytes in every array.
  bool equal(std::uint32_t u, std::uint32_t v) const {
    for (const Array& a : arrays_)
      if (std::memcmp(a.data + std::size_t(u) * a.bytes, a.data + std::size_t(v) * a.bytes, a.bytes) != 0) return false;
    return true;
  }

  static constexpr std::uint64_t kSeed = 0x243f6a8885a308d3ull;
  static std::uint64_t mix(std::uint64_t h, std::uint32_t word) { return (h ^ word) * 0x9e3779b97f4a7c15ull; }
  static std::uint64_t finish(std::uint64_t h) {
    h ^= h >> 29;
    h *= 0xbf58476d1ce4e5b9ull;
    return h ^ (h >> 32);
  }

 private:
  struct Array {
    const unsigned char* data;
    std::size_t bytes;
  };
  std::vector<Array> arrays_;
};

}  // namespace deepcut::detail
