// SPDX-License-Identifier: MIT
#pragma once
// Constants and small helpers of the soft-body clustering (private to core): shared by
// clustering.cpp (build, apply) and clustering_report.cpp (stats, checks, radius search).

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "deepcut/core/errors.h"
#include "deepcut/core/surface_mesh.h"

namespace deepcut::clustering_detail {

/// Raw weights never reach 0, so a vertex exactly at distance rho keeps a usable influence.
constexpr float kMinRawWeight = 1e-6f;
/// Relative slack on "within rho" for vertices placed by interpolation (a lerp of two points
/// inside a ball is inside it, up to float rounding).
constexpr float kRadiusSlack = 1e-5f;

inline float falloff(float d2, float rho2) {
  const float f = std::max(0.0f, 1.0f - d2 / rho2);
  return std::max(f * f, kMinRawWeight);
}

inline float distance2(const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 d = a - b;
  return glm::dot(d, d);
}

inline void check_radius(float radius, const char* what) {
  if (!(radius > 0.0f) || !std::isfinite(radius))
    throw Error(
        ErrorCode::InvalidArgument,
        std::string(what) + ": radius must be a positive finite number, got " + std::to_string(radius));
}

inline void check_rest(const SurfaceMesh& mesh, const std::vector<glm::vec3>& rest, const char* what) {
  if (rest.size() != mesh.vertex_count())
    throw Error(ErrorCode::InvalidArgument, std::string(what) + ": " + std::to_string(rest.size()) +
                                                " rest positions for a mesh of " +
                                                std::to_string(mesh.vertex_count()) + " vertices");
}

}  // namespace deepcut::clustering_detail
