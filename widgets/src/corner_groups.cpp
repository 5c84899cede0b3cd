// SPDX-License-Identifier: MIT
#include "corner_groups.h"

#include <algorithm>
#include <atomic>

#include "deepcut/core/parallel.h"

namespace deepcut {

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
  std::atomic<bool> one_vertex{false};
  by_range([&](std::size_t lo, std::size_t hi) {
    bool same = false;
    for (std::size_t f = 0; f < slots; ++f) {
      if (mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)))) continue;
      const Triangle& t = faces[f];
      same |= t[0] == t[1] && t[1] == t[2];
      for (int k = 0; k < 3; ++k)
        if (t[k].index >= lo && t[k].index < hi) ++g.offset[t[k].index + 1];
    }
    if (same) one_vertex.store(true, std::memory_order_relaxed);
  });
  for (std::size_t v = 0; v < vertices; ++v) g.offset[v + 1] += g.offset[v];
  g.one_vertex_face = one_vertex.load();
  g.corner.resize(g.offset[vertices]);
  by_range([&](std::size_t lo, std::size_t hi) {
    std::vector<std::uint32_t> cursor(g.offset.begin() + static_cast<std::ptrdiff_t>(lo),
                                      g.offset.begin() + static_cast<std::ptrdiff_t>(hi));
    for (std::size_t f = 0; f < slots; ++f) {
      if (mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f)))) continue;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = faces[f][k].index;
        if (v >= lo && v < hi) g.corner[cursor[v - lo]++] = static_cast<std::uint32_t>(3 * f + static_cast<std::size_t>(k));
      }
    }
  });
  return g;
}

}  // namespace deepcut
