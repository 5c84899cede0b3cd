// SPDX-License-Identifier: MIT
#pragma once
// Constants and small helpers of the soft-body clustering (private to core): shared by
// clustering.cpp (build, apply) and clustering_report.cpp (stats, checks, radius search); the
// union-find and the grouping of the split into connected parts; the seed sampling
// (clustering_seeds.cpp).

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
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

/// Farthest-point sampling of the points ids[0 .. count) (ascending) of `grid` until every point
/// lies within `cover` of a seed. The first seed is the point farthest from the bounding-box
/// centre; each next one the point farthest from the seeds so far; ties go to the smaller index.
/// The seeds do not depend on the thread count.
std::vector<std::uint32_t> farthest_point_seeds(const std::vector<glm::vec3>& rest, const std::uint32_t* ids,
                                                std::size_t count, const PointGrid& grid, float cover);

// The connected parts of one particle's members: the largest (the first in root order on ties)
// and the others, each sorted by vertex.
struct Parts {
  std::vector<std::uint32_t> main;
  std::vector<std::vector<std::uint32_t>> minors;
};

// `by_root`: (union-find root, vertex) for every member; sorted here.
inline Parts parts_by_root(std::vector<std::pair<std::uint32_t, std::uint32_t>>& by_root) {
  std::sort(by_root.begin(), by_root.end());
  // Parts as ranges of by_root.
  std::size_t best_begin = 0, best_size = 0;
  for (std::size_t i = 0; i < by_root.size();) {
    std::size_t j = i;
    while (j < by_root.size() && by_root[j].first == by_root[i].first) ++j;
    if (j - i > best_size) best_begin = i, best_size = j - i;
    i = j;
  }
  Parts parts;
  for (std::size_t i = 0; i < by_root.size();) {
    std::size_t j = i;
    while (j < by_root.size() && by_root[j].first == by_root[i].first) ++j;
    std::vector<std::uint32_t>& out = i == best_begin ? parts.main : parts.minors.emplace_back();
    for (std::size_t k = i; k < j; ++k) out.push_back(by_root[k].second);
    std::sort(out.begin(), out.end());
    i = j;
  }
  return parts;
}

// The parts of one particle's members `m` from their roots (`root[i]` that of m[i]), as
// parts_by_root gives them, without its sorts: each member is filed under its root (looked up
// among the few roots met so far, the last one first), in the order of `m`, which keeps every
// part ascending. Only for strictly ascending `m` and at most kMaxParts parts: else nothing (the
// caller uses parts_by_root). `group`: scratch.
inline std::optional<Parts> parts_by_group(const std::vector<std::uint32_t>& m,
                                           const std::vector<std::uint32_t>& root,
                                           std::vector<std::uint8_t>& group) {
  constexpr std::size_t kMaxParts = 16;
  std::uint32_t roots[kMaxParts];
  std::size_t sizes[kMaxParts];
  std::size_t count = 0, last = 0;
  group.resize(m.size());
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (i > 0 && !(m[i - 1] < m[i])) return std::nullopt;
    if (count == 0 || roots[last] != root[i]) {
      last = 0;
      while (last < count && roots[last] != root[i]) ++last;
      if (last == count) {
        if (count == kMaxParts) return std::nullopt;
        roots[count] = root[i];
        sizes[count++] = 0;
      }
    }
    ++sizes[last];
    group[i] = static_cast<std::uint8_t>(last);
  }
  if (count == 0) return Parts{};
  // The parts in root order; the largest (the first in that order on ties) is the main one.
  std::size_t order[kMaxParts];
  for (std::size_t g = 0; g < count; ++g) order[g] = g;
  std::sort(order, order + count, [&](std::size_t a, std::size_t b) { return roots[a] < roots[b]; });
  std::size_t best = order[0];
  for (std::size_t k = 1; k < count; ++k)
    if (sizes[order[k]] > sizes[best]) best = order[k];
  Parts parts;
  parts.minors.resize(count - 1);
  std::vector<std::uint32_t>* out[kMaxParts];
  for (std::size_t k = 0, minor = 0; k < count; ++k)
    out[order[k]] = order[k] == best ? &parts.main : &parts.minors[minor++];
  for (std::size_t g = 0; g < count; ++g) out[g]->reserve(sizes[g]);
  for (std::size_t i = 0; i < m.size(); ++i) out[group[i]]->push_back(m[i]);
  return parts;
}

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
