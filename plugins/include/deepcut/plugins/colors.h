// SPDX-License-Identifier: MIT
#pragma once
/// @file colors.h
/// Colour scales the inspectors share, so the same thing looks the same everywhere.

#include <cstddef>
#include <glm/glm.hpp>
#include <glm/gtc/type_precision.hpp>
#include <vector>

namespace deepcut::plugins {

/// Blender's weight-paint ramp: 0 blue, 0.25 cyan, 0.5 green, 0.75 yellow, 1 red.
/// @param w  weight, clamped to [0, 1].
glm::vec3 weight_color(float w);
/// The stops of `weight_color`, for a colour bar.
std::vector<glm::vec3> weight_ramp();

/// The i-th of a sequence of well separated hues (golden-angle spacing), for categories such as
/// joints, components or particles. Deterministic.
glm::vec3 category_color(std::size_t i);

/// A lighter, less saturated version of `c` (`amount` in [0, 1], default 0.5).
glm::vec3 pastel(const glm::vec3& c, float amount = 0.5f);

/// RGB in [0, 1] to 8 bits per channel.
glm::u8vec3 to_rgb8(const glm::vec3& c);

/// Fixed colours of things every inspector may draw.
namespace palette {
inline constexpr glm::vec3 kNeutral{0.72f, 0.72f, 0.70f};     ///< surface with nothing to show
inline constexpr glm::vec3 kUnskinned{0.45f, 0.45f, 0.47f};   ///< surface without skin data
inline constexpr glm::vec3 kPicked{1.0f, 1.0f, 1.0f};         ///< the picked element
inline constexpr glm::vec3 kHighlight{1.0f, 0.55f, 0.1f};     ///< its neighbourhood
inline constexpr glm::vec3 kFlagged{1.0f, 0.1f, 0.85f};       ///< elements with a problem
inline constexpr glm::vec3 kBoundary{0.15f, 0.55f, 1.0f};     ///< boundary edges
inline constexpr glm::vec3 kNonManifold{1.0f, 0.12f, 0.12f};  ///< non-manifold edges
inline constexpr glm::vec3 kSeam{0.2f, 0.95f, 0.35f};         ///< seam edges
inline constexpr glm::vec3 kBone{0.55f, 0.75f, 1.0f};         ///< skeleton bones
}  // namespace palette

}  // namespace deepcut::plugins
