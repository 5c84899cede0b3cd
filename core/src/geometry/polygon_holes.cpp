// SPDX-License-Identifier: MIT
// The holes of a polygon to triangulate: each bridged into its outer loop (bridge_hole), and the
// loops of a cap or a kept part sorted into outer loops and their holes (loop_polygons).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>
#include <utility>

#include "geometry/polygon_triangulation.h"
#include "geometry/predicates.h"

namespace deepcut::geometry {
namespace {

// The (outer, hole) position pairs a bridge may join, in the order they are tried.
std::vector<std::pair<std::size_t, std::size_t>> bridge_candidates(const std::vector<glm::dvec2>& pts,
                                                                   const std::vector<std::uint32_t>& outer,
                                                                   const std::vector<std::uint32_t>& hole,
                                                                   HoleBridge rule) {
  std::vector<std::pair<std::size_t, std::size_t>> tries;
  tries.reserve(rule == HoleBridge::kRightmost ? outer.size() : outer.size() * hole.size());
  if (rule == HoleBridge::kRightmost) {
    std::size_t hi = 0;
    for (std::size_t i = 1; i < hole.size(); ++i)
      if (pts[hole[i]].x > pts[hole[hi]].x) hi = i;
    const glm::dvec2 h = pts[hole[hi]];
    std::vector<std::size_t> order(outer.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return glm::length(pts[outer[a]] - h) < glm::length(pts[outer[b]] - h);
    });
    for (std::size_t o : order) tries.emplace_back(o, hi);
    return tries;
  }
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
  pairs.reserve(outer.size() * hole.size());
  for (std::size_t o = 0; o < outer.size(); ++o)
    for (std::size_t h = 0; h < hole.size(); ++h) pairs.emplace_back(glm::length(pts[outer[o]] - pts[hole[h]]), o, h);
  std::sort(pairs.begin(), pairs.end());
  for (const auto& [dist, o, h] : pairs) tries.emplace_back(o, h);
  return tries;
}

// `outer` up to position o, the hole once around from position h back to it, then `outer` from o.
std::vector<std::uint32_t> join_at(const std::vector<std::uint32_t>& outer, const std::vector<std::uint32_t>& hole,
                                   std::size_t o, std::size_t h, bool spliced) {
  std::vector<std::uint32_t> merged;
  merged.reserve(outer.size() + hole.size() + 2);
  merged.insert(merged.end(), outer.begin(), outer.begin() + static_cast<std::ptrdiff_t>(o) + 1);
  for (std::size_t k = spliced ? 1 : 0; k <= hole.size(); ++k) merged.push_back(hole[(h + k) % hole.size()]);
  merged.insert(merged.end(), outer.begin() + static_cast<std::ptrdiff_t>(o) + (spliced ? 1 : 0), outer.end());
  return merged;
}

}  // namespace

std::vector<std::uint32_t> bridge_hole(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& outer,
                                       const std::vector<std::uint32_t>& hole,
                                       const std::vector<std::vector<std::uint32_t>>& others, HoleBridge rule) {
  if (outer.empty() || hole.empty()) return outer;
  if (rule == HoleBridge::kNearestPair)
    for (std::size_t o = 0; o < outer.size(); ++o)
      for (std::size_t h = 0; h < hole.size(); ++h)
        if (outer[o] == hole[h]) return join_at(outer, hole, o, h, true);
  const auto tries = bridge_candidates(pts, outer, hole, rule);
  auto [bo, bh] = tries.front();
  for (const auto& [o, h] : tries) {
    const glm::dvec2 &p = pts[outer[o]], &q = pts[hole[h]];
    bool blocked = false;
    auto check = [&](const std::vector<std::uint32_t>& loop) {
      for (std::size_t i = 0; i < loop.size() && !blocked; ++i)
        blocked = segments_cross(p, q, pts[loop[i]], pts[loop[(i + 1) % loop.size()]]);
    };
    check(outer);
    check(hole);
    if (rule == HoleBridge::kNearestPair)
      for (const auto& other : others) check(other);
    if (!blocked) {
      bo = o;
      bh = h;
      break;
    }
  }
  return join_at(outer, hole, bo, bh, false);
}

LoopPolygons loop_polygons(const std::vector<glm::dvec2>& points, const std::vector<std::vector<std::uint32_t>>& loops,
                           int outer_sign) {
  // Work counter-clockwise: mirror when the outer loops are clockwise (mirroring reverses
  // orientation once, so the triangles already have the outer loops' orientation).
  LoopPolygons out;
  out.pts = points;
  if (outer_sign < 0)
    for (auto& p : out.pts) p.x = -p.x;
  const auto& pts = out.pts;
  std::vector<std::size_t> holes;
  std::vector<double> area(loops.size());
  for (std::size_t i = 0; i < loops.size(); ++i) {
    if (loops[i].size() < 3) continue;
    area[i] = signed_area2(pts, loops[i]);
    if (area[i] > 0) out.outers.push_back(i);
    else if (area[i] < 0) holes.push_back(i);
  }
  // The hole lists by outer loop, then by position in `outers`.
  std::vector<std::vector<std::vector<std::uint32_t>>> holes_of(loops.size());
  for (std::size_t h : holes) {
    std::size_t owner = loops.size();
    for (std::size_t o : out.outers)
      if (point_in_loop(pts, loops[o], pts[loops[h][0]]) && (owner == loops.size() || area[o] < area[owner])) owner = o;
    if (owner != loops.size()) holes_of[owner].push_back(loops[h]);
  }
  out.holes.reserve(out.outers.size());
  for (std::size_t o : out.outers) out.holes.push_back(std::move(holes_of[o]));
  return out;
}

}  // namespace deepcut::geometry
