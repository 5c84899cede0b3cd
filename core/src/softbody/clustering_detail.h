// SPDX-License-Identifier: MIT
#pragma once
// Constants and small helpers of the soft-body clustering (private to core), shared by the files
// that include it: clustering_build.cpp (Clusters::build), clustering_seeds.cpp (the seed
// sampling), clustering_split.cpp (splitting particles into connected parts),
// clustering_parts.cpp (grouping a particle's members by part), clustering_apply.cpp (following
// an edit log) and clustering_report.cpp (stats, checks, radius search). Here: the falloff and the
// argument checks; the seed sampling's entry point (farthest_point_seeds, over a PointGrid of
// point_grid.h); the union-find and the grouping of the split; the faces a split walks.

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/errors.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/softbody/clustering.h"
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

// Scratch of parts_by_group, kept across calls so that they allocate nothing once grown.
struct PartsScratch {
  std::vector<std::uint32_t> group;     // per member: its part's number
  std::vector<std::uint32_t> distinct;  // the roots, sorted and unique (more than kLinearRoots)
  std::vector<std::uint32_t> sizes;     // per part: its member count (more than kLinearRoots)
  std::vector<std::uint32_t> slot;      // per part: the main part or its minor (likewise)
};

// The parts of one particle's members `m` (strictly ascending) from their roots (`root[i]` that
// of m[i]), without sorting any part: each member is filed under its root's part in the order of
// `m`, which keeps every part ascending. The parts are numbered by a linear search among the
// roots met so far (the last one first) while there are at most kLinearRoots of them; past
// that, by a binary search in the sorted unique list of all the roots. The largest part (the first
// in root order on ties) is the main one, the others the minors in root order. In
// clustering_parts.cpp.
Parts parts_by_group(const std::vector<std::uint32_t>& m, const std::vector<std::uint32_t>& root,
                     PartsScratch& scratch);

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

// ------------------------------------------------------------------------------------------------
// The faces Clusters::split_disconnected walks: `walk(fn)` calls `fn(triangle)` for (at least)
// every live face around the members of the listed particles. split_disconnected is compiled in
// clustering_split.cpp for these three only (the declarations at the end of this file).

// Every live face, over the pool (a build: the split's unions do not depend on the faces' order).
class AllFacesParallel {
 public:
  explicit AllFacesParallel(const SurfaceMesh& mesh) : mesh_(mesh) {}
  template <class Fn>
  void operator()(Fn&& fn) const {
    // The chunks capture the mesh itself, not this walker: one load less per face (the unions'
    // atomics keep the compiler from holding the mesh's address in a register).
    const SurfaceMesh& mesh = mesh_;
    parallel_for(mesh.face_slots(), 8192, [&](std::size_t b, std::size_t e) {
      for (std::size_t f = b; f < e; ++f) {
        const FaceId id(static_cast<std::uint32_t>(f));
        if (!mesh.is_deleted(id)) fn(mesh.face(id));
      }
    });
  }

 private:
  const SurfaceMesh& mesh_;
};

// Every live face, in order on the calling thread (an apply without adjacency).
class AllFaces {
 public:
  explicit AllFaces(const SurfaceMesh& mesh) : mesh_(mesh) {}
  template <class Fn>
  void operator()(Fn&& fn) const {
    mesh_.for_each_face([&](FaceId, const Triangle& t) { fn(t); });
  }

 private:
  const SurfaceMesh& mesh_;
};

// The live faces around the members of the touched particles (an apply with adjacency), each
// visited once without a visited set: a vertex is visited from its first touched particle, a
// face from its first such vertex.
class FacesAroundParticles {
 public:
  FacesAroundParticles(const SurfaceMesh& mesh, const Adjacency& adjacency, const Clusters& clusters,
                       const std::vector<std::uint32_t>& touched, const std::vector<std::uint8_t>& is_touched)
      : mesh_(mesh), adjacency_(adjacency), clusters_(clusters), touched_(touched), is_touched_(is_touched) {}

  template <class Fn>
  void operator()(Fn&& fn) const {
    for (std::uint32_t p : touched_)
      for (std::uint32_t v : clusters_.members(p)) {
        if (v >= adjacency_.vertex_count() || first_touched(v) != p) continue;
        for (const FaceId f : adjacency_.vertex_faces(VertexId(v))) {
          const Triangle& t = mesh_.face(f);
          std::uint32_t first = kInvalidIndex;
          for (int k = 0; k < 3 && first == kInvalidIndex; ++k)
            if (first_touched(t[k].index) != kInvalidIndex) first = t[k].index;
          if (first == v) fn(t);
        }
      }
  }

 private:
  std::uint32_t first_touched(std::uint32_t v) const {
    for (const Influence& in : clusters_.influences(VertexId(v)))
      if (in.particle < is_touched_.size() && is_touched_[in.particle]) return in.particle;
    return kInvalidIndex;
  }

  const SurfaceMesh& mesh_;
  const Adjacency& adjacency_;
  const Clusters& clusters_;
  const std::vector<std::uint32_t>& touched_;
  const std::vector<std::uint8_t>& is_touched_;
};

}  // namespace deepcut::clustering_detail

namespace deepcut {

// Compiled in clustering_split.cpp.
extern template std::size_t Clusters::split_disconnected<clustering_detail::AllFacesParallel>(
    const std::vector<std::uint32_t>&, clustering_detail::AllFacesParallel&&,
    std::vector<ClusterUpdate::NewParticle>&);
extern template std::size_t Clusters::split_disconnected<clustering_detail::AllFaces>(
    const std::vector<std::uint32_t>&, clustering_detail::AllFaces&&,
    std::vector<ClusterUpdate::NewParticle>&);
extern template std::size_t Clusters::split_disconnected<clustering_detail::FacesAroundParticles>(
    const std::vector<std::uint32_t>&, clustering_detail::FacesAroundParticles&&,
    std::vector<ClusterUpdate::NewParticle>&);

}  // namespace deepcut
