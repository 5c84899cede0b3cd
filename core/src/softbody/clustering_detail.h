// SPDX-License-Identifier: MIT
#pragma once
// Constants and small helpers of the soft-body clustering (private to core): shared by
// clustering.cpp (build, apply) and clustering_report.cpp (stats, checks, radius search); the
// union-find of the split into connected parts; the seed sampling (clustering_seeds.cpp).

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "deepcut/core/errors.h"
#include "deepcut/core/parallel.h"
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

class PointGrid;

/// Farthest-point sampling of the points `ids` (ascending) of `grid` until every point lies
/// within `cover` of a seed. The first seed is the point farthest from the bounding-box centre;
/// each next one the point farthest from the seeds so far; ties go to the smaller index. The
/// seeds do not depend on the thread count.
std::vector<std::uint32_t> farthest_point_seeds(const std::vector<glm::vec3>& rest,
                                                const std::vector<std::uint32_t>& ids, const PointGrid& grid,
                                                float cover);

// A union-find over [0, n), every element a set of its own at first (set up in parallel), whose
// unions may run on several threads at once. The smaller root always wins, so a set's root is its
// smallest element whatever the order of the unions: the same roots as a serial union-find
// linking the larger root under the smaller.
class ConcurrentUnionFind {
 public:
  explicit ConcurrentUnionFind(std::size_t n) : up_(new std::atomic<std::uint32_t>[n]) {
    parallel_for(n, 1 << 16, [&](std::size_t b, std::size_t e) {
      for (std::size_t x = b; x < e; ++x) up_[x].store(static_cast<std::uint32_t>(x), std::memory_order_relaxed);
    });
  }
  std::uint32_t find(std::uint32_t x) {
    for (;;) {
      std::uint32_t up = up_[x].load(std::memory_order_relaxed);
      if (up == x) return x;
      const std::uint32_t top = up_[up].load(std::memory_order_relaxed);
      // Path halving: `top` is an ancestor of x too, whatever other threads did meanwhile.
      if (top != up) up_[x].compare_exchange_weak(up, top, std::memory_order_relaxed);
      x = top;
    }
  }
  void unite(std::uint32_t x, std::uint32_t y) {
    for (;;) {
      x = find(x);
      y = find(y);
      if (x == y) return;
      if (x < y) std::swap(x, y);
      std::uint32_t expected = x;  // link the larger root under the smaller
      if (up_[x].compare_exchange_strong(expected, y, std::memory_order_relaxed)) return;
    }
  }

 private:
  std::unique_ptr<std::atomic<std::uint32_t>[]> up_;
};

}  // namespace deepcut::clustering_detail
