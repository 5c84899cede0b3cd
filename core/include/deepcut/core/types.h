// SPDX-License-Identifier: MIT
#pragma once
/// @file types.h
/// Strong element ids and the GLM types used across the public API.

#include <cstdint>
#include <functional>
#include <limits>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace deepcut {

inline constexpr std::uint32_t kInvalidIndex = std::numeric_limits<std::uint32_t>::max();

/// A strongly typed index: a `VertexId` cannot be passed where a `FaceId` is expected.
template <class Tag>
struct Id {
  std::uint32_t index = kInvalidIndex;

  constexpr Id() = default;
  constexpr explicit Id(std::uint32_t i) : index(i) {}
  constexpr bool valid() const { return index != kInvalidIndex; }
  constexpr bool operator==(Id o) const { return index == o.index; }
  constexpr bool operator!=(Id o) const { return index != o.index; }
  constexpr bool operator<(Id o) const { return index < o.index; }
};

struct VertexTag {};
struct FaceTag {};
using VertexId = Id<VertexTag>;
using FaceId = Id<FaceTag>;

/// An infinite plane through `point` with unit-or-not `normal` (only its direction matters).
struct Plane {
  glm::vec3 point{0.0f};
  glm::vec3 normal{0.0f, 1.0f, 0.0f};
};

/// Axis-aligned box; `empty()` until something is added.
struct BoundingBox {
  glm::vec3 min{std::numeric_limits<float>::max()};
  glm::vec3 max{std::numeric_limits<float>::lowest()};

  bool empty() const { return min.x > max.x; }
  void add(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void add(const BoundingBox& b) {
    if (!b.empty()) {
      add(b.min);
      add(b.max);
    }
  }
  /// Length of the diagonal; 0 when empty. This is "the model size" for relative tolerances.
  float diagonal() const { return empty() ? 0.0f : glm::length(max - min); }
};

}  // namespace deepcut

template <class Tag>
struct std::hash<deepcut::Id<Tag>> {
  std::size_t operator()(deepcut::Id<Tag> id) const noexcept { return std::hash<std::uint32_t>()(id.index); }
};
