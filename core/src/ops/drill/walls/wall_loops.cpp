// SPDX-License-Identifier: MIT
// A shell's rims as loops in the wall plane: run the other way, split where a rim touches itself,
// folded where one crosses itself, and split into sheets where the shell passes through itself.
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "ops/drill/walls/wall_shell.h"

namespace deepcut::drill {
namespace {

// The shell's rim points (shell.pts) and loops, in the frame the wall is built in.
bool rim_loops(WallShell& shell, const WallContext& ctx) {
  const std::vector<std::size_t>& hole_ids = shell.hole_ids;
  // The end disk whose rims are mapped without distortion is the one at A: when more rim
  // vertices lie on the disk at B, the wall is built in the reversed frame (B to A).
  const double tol = shell.tol;
  int at_a = 0, at_b = 0;
  for (std::size_t h : hole_ids)
    for (VertexId v : ctx.rims[h].vertices) {
      const double sv = ctx.cyl.s(ctx.posed(v));
      at_a += std::abs(sv) <= tol;
      at_b += std::abs(sv - ctx.cyl.len) <= tol;
    }
  CylinderFrame reversed = ctx.cyl;
  reversed.a = ctx.cyl.a + ctx.cyl.len * ctx.cyl.d;
  reversed.d = -ctx.cyl.d;
  reversed.w = -ctx.cyl.w;
  shell.map.cy = at_b > at_a ? reversed : ctx.cyl;
  const CylinderFrame& cy = shell.map.cy;
  std::vector<WallPt>& pts = shell.pts;
  double& s_lo = shell.s_lo;
  double& s_hi = shell.s_hi;
  for (std::size_t h : hole_ids) {
    const Rim& hole = ctx.rims[h];
    // The wall runs along each rim the other way. A rim that touches itself (a vertex on the
    // cylinder where two arcs of the rim meet) is split there into simple loops.
    std::vector<std::uint32_t> stack;
    std::unordered_map<std::uint32_t, std::size_t> at;  // vertex -> position in stack
    for (std::size_t i = hole.vertices.size(); i-- > 0;) {
      const VertexId v = hole.vertices[i];
      const auto seen = at.find(v.index);
      if (seen != at.end()) {
        const std::size_t first = seen->second;
        std::vector<std::uint32_t> loop(stack.begin() + static_cast<std::ptrdiff_t>(first), stack.end());
        for (std::size_t k = first + 1; k < stack.size(); ++k) at.erase(pts[stack[k]].v.index);
        stack.resize(first + 1);
        if (loop.size() >= 3) {
          shell.rim_loops.push_back(std::move(loop));
          shell.loop_hole.push_back(h);
        }
        continue;
      }
      WallPt w;
      if (!classify(cy, shell.tol, ctx.posed(v), w)) return false;
      w.v = v;
      s_lo = std::min(s_lo, std::clamp(w.s, 0.0, cy.len));
      s_hi = std::max(s_hi, std::clamp(w.s, 0.0, cy.len));
      at[v.index] = stack.size();
      stack.push_back(static_cast<std::uint32_t>(pts.size()));
      pts.push_back(w);
    }
    if (stack.size() >= 3) {
      shell.rim_loops.push_back(std::move(stack));
      shell.loop_hole.push_back(h);
    }
  }
  return true;
}

// Loops of one shell never cross, unless the shell intersects itself (a limb modelled into
// the body): then the loops form two sheets, each walled on its own (crossing loops go to
// different sheets; the others to the first sheet they are consistent with, largest first).
bool split_sheets(WallShell& shell) {
  const Loops& rim_loops = shell.rim_loops;
  const std::vector<glm::dvec2>& xy = shell.xy;
  std::vector<std::size_t> seg_loop;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> all_segments;
  for (std::size_t li = 0; li < rim_loops.size(); ++li)
    for (std::size_t i = 0; i < rim_loops[li].size(); ++i) {
      all_segments.emplace_back(rim_loops[li][i], rim_loops[li][(i + 1) % rim_loops[li].size()]);
      seg_loop.push_back(li);
    }
  std::vector<std::vector<std::size_t>> crossing(rim_loops.size());
  for (std::size_t i = 0; i < all_segments.size(); ++i)
    for (std::size_t j = i + 1; j < all_segments.size(); ++j) {
      const auto [a, b] = all_segments[i];
      const auto [c, d] = all_segments[j];
      if (a == c || a == d || b == c || b == d) continue;
      if (geometry::segments_cross(xy[a], xy[b], xy[c], xy[d])) {
        if (seg_loop[i] == seg_loop[j]) return false;  // a loop crossing itself
        crossing[seg_loop[i]].push_back(seg_loop[j]);
        crossing[seg_loop[j]].push_back(seg_loop[i]);
      }
    }
  std::vector<int>& sheet = shell.sheet;
  sheet.assign(rim_loops.size(), -1);
  for (std::size_t li = 0; li < rim_loops.size(); ++li) {
    if (sheet[li] >= 0 || crossing[li].empty()) continue;
    std::vector<std::size_t> queue = {li};
    sheet[li] = 0;
    for (std::size_t qi = 0; qi < queue.size(); ++qi)
      for (std::size_t other : crossing[queue[qi]]) {
        if (sheet[other] < 0) {
          sheet[other] = 1 - sheet[queue[qi]];
          queue.push_back(other);
        } else if (sheet[other] == sheet[queue[qi]]) {
          return false;  // three sheets through one spot
        }
      }
  }
  std::vector<std::size_t> free_loops;
  for (std::size_t li = 0; li < rim_loops.size(); ++li)
    if (sheet[li] < 0) free_loops.push_back(li);
  std::sort(free_loops.begin(), free_loops.end(), [&](std::size_t x, std::size_t y) {
    return std::abs(geometry::signed_area2(xy, rim_loops[x])) >
           std::abs(geometry::signed_area2(xy, rim_loops[y]));
  });
  for (std::size_t li : free_loops) {
    int c = 0;
    for (int k = 0; k < 2 && sheet[li] < 0; ++k)
      if (consistent(xy, shell.sheet_loops(k, li), c)) sheet[li] = k;
    if (sheet[li] < 0) return false;
  }
  return true;
}

}  // namespace

// A rim crosses itself on the cylinder where the posed surface passes through itself (a skin
// folding at a joint). No wall lying on the cylinder can close it, so the wall folds with the
// surface: where steps a->b and c->d cross, the loop is short-cut by a->d, and the lobe cut
// off (b ... c, the shorter side) is closed by the triangles (a, b, c), (a, c, d) and a fan
// from b over the lobe, all in the loop's direction (closed and consistently oriented; it
// overlaps itself there as the surface does).
// The wall maps the loops again per sheet (over its own extent), where a fold can show that
// the first map did not: each map is folded.
bool fold_loops(const std::vector<glm::dvec2>& xy, Loops& loops_to_fold,
                std::vector<std::pair<std::size_t, geometry::LocalTri>>& lobes) {
  for (int fold_round = 0; fold_round < 8; ++fold_round) {
    bool found = false;
    for (std::size_t li = 0; li < loops_to_fold.size() && !found; ++li) {
      auto& l = loops_to_fold[li];
      const std::size_t m = l.size();
      for (std::size_t i = 0; i < m && !found; ++i)
        for (std::size_t j = i + 2; j < m && !found; ++j) {
          if ((j + 1) % m == i) continue;
          const std::uint32_t a = l[i], b = l[(i + 1) % m], c = l[j], d = l[(j + 1) % m];
          if (a == c || a == d || b == c || b == d) continue;
          if (!geometry::segments_cross(xy[a], xy[b], xy[c], xy[d])) continue;
          found = true;
          // Steps i (a->b) and j (c->d); the lobe is b..c (positions i+1..j) or d..a (j+1..i).
          std::size_t first = i, second = j;
          if (j - i > m - (j - i)) std::swap(first, second);
          const std::uint32_t fa = l[first], fb = l[(first + 1) % m], fc = l[second],
                              fd = l[(second + 1) % m];
          if (m - ((second + m - first) % m) < 3) return false;  // nothing would be left of the loop
          lobes.emplace_back(li, geometry::LocalTri{fa, fb, fc});
          lobes.emplace_back(li, geometry::LocalTri{fa, fc, fd});
          for (std::size_t k = (first + 1) % m; (k + 1) % m != second; k = (k + 1) % m)
            lobes.emplace_back(li, geometry::LocalTri{fb, l[(k + 1) % m], l[(k + 2) % m]});
          std::vector<std::uint32_t> kept;
          for (std::size_t k = (second + 1) % m;; k = (k + 1) % m) {
            kept.push_back(l[k]);
            if (k == first) break;
          }
          l = std::move(kept);
        }
    }
    if (!found) break;
  }
  return true;
}

bool shell_loops(WallShell& shell, const WallContext& ctx) {
  if (!rim_loops(shell, ctx)) return false;
  // The plane map (and its inverse, for points placed in the plane).
  shell.map.base = shell.s_lo;
  shell.map.kappa = std::max(1.0, (shell.s_hi - shell.s_lo) / (kWallSpan * shell.map.cy.r));
  shell.map.mobius = false;
  shell.map.z0 = glm::dvec2(0.0);
  shell.map_points();
  if (!fold_loops(shell.xy, shell.rim_loops, shell.lobe_tris)) return false;
  return split_sheets(shell);
}

}  // namespace deepcut::drill
