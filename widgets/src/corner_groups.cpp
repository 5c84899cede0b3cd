// SPDX-License-Identifier: MIT
#include "corner_groups.h"

#include <algorithm>
#include <atomic>
#include <type_traits>

#include "deepcut/core/parallel.h"

namespace deepcut {

namespace {
constexpr std::size_t kFaceGrain = 16384;  // faces per parallel chunk
}  // namespace

CornerGroups group_corners(const SurfaceMesh& mesh) {
  CornerGroups g;
  const std::size_t vertices = mesh.vertex_count(), slots = mesh.face_slots();
  const Triangle* faces = mesh.faces().data();
  g.offset.assign(vertices + 1, 0);
  // Vertex ranges, each scanning every face for its own vertices: all writes of a range are to
  // its vertices' entries, so the table is the same for any number of ranges.
  const std::size_t ranges = std::min<std::size_t>(thread_count(), 8);
  auto by_range = [&](auto&& fn) {
    parallel_for(ranges, 1, [&](std::size_t b, std::size_t e) {
      for (std::size_t r = b; r < e; ++r) fn(vertices * r / ranges, vertices * (r + 1) / ranges);
    });
  };
  // Every corner of a live face, to `fn(vertex, corner)` where the vertex is in [lo, hi) (one
  // unsigned comparison); no test per face for deletion when no face is deleted.
  const bool all_live = mesh.face_count() == slots;
  auto scan = [&](std::size_t lo, std::size_t hi, auto&& fn) {
    auto run = [&](auto live) {
      for (std::size_t f = 0; f < slots; ++f) {
        if (!decltype(live)::value && mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)))) continue;
        for (std::size_t k = 0; k < 3; ++k) {
          const std::uint32_t v = faces[f][static_cast<int>(k)].index;
          if (v - lo < hi - lo) fn(v, static_cast<std::uint32_t>(3 * f + k));
        }
      }
    };
    if (all_live)
      run(std::true_type{});
    else
      run(std::false_type{});
  };
  by_range([&](std::size_t lo, std::size_t hi) {
    std::uint32_t* count = g.offset.data() + 1;
    scan(lo, hi, [&](std::uint32_t v, std::uint32_t) { ++count[v]; });
  });
  std::atomic<bool> one_vertex{false};
  parallel_for(slots, kFaceGrain, [&](std::size_t b, std::size_t e) {
    bool same = false;
    for (std::size_t f = b; f < e; ++f) {
      const Triangle& t = faces[f];
      same |= t[0] == t[1] && t[1] == t[2] && !mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)));
    }
    if (same) one_vertex.store(true, std::memory_order_relaxed);
  });
  g.one_vertex_face = one_vertex.load();
  for (std::size_t v = 0; v < vertices; ++v) g.offset[v + 1] += g.offset[v];
  g.corner.resize(g.offset[vertices]);
  by_range([&](std::size_t lo, std::size_t hi) {
    std::vector<std::uint32_t> cursor(g.offset.begin() + static_cast<std::ptrdiff_t>(lo),
                                      g.offset.begin() + static_cast<std::ptrdiff_t>(hi));
    std::uint32_t* const at = cursor.data();
    std::uint32_t* const corner = g.corner.data();
    scan(lo, hi, [&](std::uint32_t v, std::uint32_t c) { corner[at[v - lo]++] = c; });
  });
  return g;
}

}  // namespace deepcut
