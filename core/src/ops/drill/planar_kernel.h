// SPDX-License-Identifier: MIT
#pragma once
// The drill's planar kernel (orientation, in-circle test, ear clipping with hole bridging, and a
// Lawson-flip constrained Delaunay triangulation), kept here verbatim until it moves to
// core/src/geometry/. Private to the drill.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "ops/drill/cylinder_section.h"

namespace deepcut::drill {

inline double wrap_2pi(double x) {
  x = std::fmod(x, 2.0 * kPi);
  return x < 0.0 ? x + 2.0 * kPi : x;
}

inline double orient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// > 0 when d lies inside the circle through the counter-clockwise triangle a, b, c.
inline double incircle(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& d) {
  const double adx = a.x - d.x, ady = a.y - d.y, bdx = b.x - d.x, bdy = b.y - d.y, cdx = c.x - d.x,
               cdy = c.y - d.y;
  const double ad = adx * adx + ady * ady, bd = bdx * bdx + bdy * bdy, cd = cdx * cdx + cdy * cdy;
  return adx * (bdy * cd - bd * cdy) - ady * (bdx * cd - bd * cdx) + ad * (bdx * cdy - bdy * cdx);
}

using LocalTri = std::array<std::uint32_t, 3>;

// Ear clipping of one counter-clockwise, weakly simple polygon (indices into `pts`; a bridged
// hole repeats two points). An ear must have positive area and no other polygon point in its
// closed triangle, so points on a diagonal (collinear rim and edge points) never make T-junctions.
// Best-shaped ears first.
inline void clip_polygon(const std::vector<glm::dvec2>& pts, std::vector<std::uint32_t> poly,
                  std::vector<LocalTri>& out) {
  while (poly.size() > 3) {
    const std::size_t n = poly.size();
    std::size_t best = n;
    double best_quality = -1.0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t ia = poly[(i + n - 1) % n], ib = poly[i], ic = poly[(i + 1) % n];
      const glm::dvec2 &a = pts[ia], &b = pts[ib], &c = pts[ic];
      const double area = orient(a, b, c);
      const double longest =
          std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
      const double tiny = 1e-13 * longest;  // relative: the log-polar plane spans many scales
      if (area <= tiny) continue;
      bool contains = false;
      for (std::size_t j = 0; j < n && !contains; ++j) {
        const std::uint32_t iq = poly[j];
        if (iq == ia || iq == ib || iq == ic) continue;
        const glm::dvec2& p = pts[iq];
        contains = orient(a, b, p) >= -tiny && orient(b, c, p) >= -tiny && orient(c, a, p) >= -tiny;
      }
      if (contains) continue;
      const double quality = area / std::max(longest, 1e-300);
      if (quality > best_quality) {
        best_quality = quality;
        best = i;
      }
    }
    if (best == n) {  // no proper ear: numerically degenerate; clip the most convex corner
      double most = -std::numeric_limits<double>::max();
      for (std::size_t i = 0; i < n; ++i) {
        const double area = orient(pts[poly[(i + n - 1) % n]], pts[poly[i]], pts[poly[(i + 1) % n]]);
        if (area > most) {
          most = area;
          best = i;
        }
      }
      if (most > 0.0) out.push_back({poly[(best + n - 1) % n], poly[best], poly[(best + 1) % n]});
    } else {
      out.push_back({poly[(best + n - 1) % n], poly[best], poly[(best + 1) % n]});
    }
    poly.erase(poly.begin() + static_cast<std::ptrdiff_t>(best));
  }
  if (poly.size() == 3 && orient(pts[poly[0]], pts[poly[1]], pts[poly[2]]) > 0.0)
    out.push_back({poly[0], poly[1], poly[2]});
}

// Joins a clockwise `hole` lying inside the counter-clockwise `outer` into one weakly simple
// polygon, bridging from the hole point nearest to an outer point that sees it.
inline std::vector<std::uint32_t> bridge(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& outer,
                                  const std::vector<std::uint32_t>& hole,
                                  const std::vector<std::vector<std::uint32_t>>& others = {}) {
  auto crosses = [&](const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& d) {
    const double d1 = orient(a, b, c), d2 = orient(a, b, d), d3 = orient(c, d, a), d4 = orient(c, d, b);
    return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
  };
  // A hole that touches the outer loop at a shared point is spliced in there (no bridge).
  for (std::size_t o = 0; o < outer.size(); ++o)
    for (std::size_t h = 0; h < hole.size(); ++h)
      if (outer[o] == hole[h]) {
        std::vector<std::uint32_t> merged(outer.begin(), outer.begin() + static_cast<std::ptrdiff_t>(o) + 1);
        for (std::size_t k = 1; k <= hole.size(); ++k) merged.push_back(hole[(h + k) % hole.size()]);
        merged.insert(merged.end(), outer.begin() + static_cast<std::ptrdiff_t>(o) + 1, outer.end());
        return merged;
      }
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
  for (std::size_t o = 0; o < outer.size(); ++o)
    for (std::size_t h = 0; h < hole.size(); ++h)
      pairs.emplace_back(glm::length(pts[outer[o]] - pts[hole[h]]), o, h);
  std::sort(pairs.begin(), pairs.end());
  std::size_t bo = std::get<1>(pairs[0]), bh = std::get<2>(pairs[0]);
  for (const auto& [dist, o, h] : pairs) {
    (void)dist;
    const glm::dvec2 &p = pts[outer[o]], &q = pts[hole[h]];
    bool blocked = false;
    auto check = [&](const std::vector<std::uint32_t>& loop) {
      for (std::size_t i = 0; i < loop.size() && !blocked; ++i)
        blocked = crosses(p, q, pts[loop[i]], pts[loop[(i + 1) % loop.size()]]);
    };
    check(outer);
    check(hole);
    for (const auto& other : others) check(other);
    if (!blocked) {
      bo = o;
      bh = h;
      break;
    }
  }
  std::vector<std::uint32_t> merged;
  for (std::size_t i = 0; i <= bo; ++i) merged.push_back(outer[i]);
  for (std::size_t k = 0; k <= hole.size(); ++k) merged.push_back(hole[(bh + k) % hole.size()]);
  for (std::size_t i = bo; i < outer.size(); ++i) merged.push_back(outer[i]);
  return merged;
}

// Triangulates a counter-clockwise outer loop with at most one clockwise hole inside it.
inline std::vector<LocalTri> triangulate(const std::vector<glm::dvec2>& pts,
                                  const std::vector<std::vector<std::uint32_t>>& loops) {
  std::vector<LocalTri> out;
  clip_polygon(pts, loops.size() > 1 ? bridge(pts, loops[0], loops[1]) : loops[0], out);
  return out;
}

// A triangulation of points in the plane with neighbour links: Lawson flips to the constrained
// Delaunay triangulation (edges with one triangle are the constraints) and point insertion.
class FlipTriangulation {
 public:
  FlipTriangulation(std::vector<glm::dvec2>& pts, std::vector<LocalTri> tris)
      : pts_(pts), tris_(std::move(tris)) {
    nbr_.assign(tris_.size(), {-1, -1, -1});
    // Half-edges sorted by key (a flat table: a polygon has a few dozen); where a half-edge
    // repeats, the last triangle listing it is the one found, as a map overwritten in order gives.
    auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
    std::vector<std::pair<std::uint64_t, int>> half;
    half.reserve(3 * tris_.size());
    for (std::size_t i = 0; i < tris_.size(); ++i)
      for (int k = 0; k < 3; ++k) half.emplace_back(key(tris_[i][k], tris_[i][(k + 1) % 3]), static_cast<int>(i));
    std::stable_sort(half.begin(), half.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (std::size_t i = 0; i < tris_.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const std::uint64_t want = key(tris_[i][(k + 1) % 3], tris_[i][k]);
        auto it = std::upper_bound(half.begin(), half.end(), want,
                                   [](std::uint64_t v, const auto& x) { return v < x.first; });
        if (it == half.begin() || std::prev(it)->first != want) continue;
        if (std::prev(it)->second != static_cast<int>(i)) nbr_[i][k] = std::prev(it)->second;
      }
  }

  const std::vector<LocalTri>& triangles() const { return tris_; }

  /// True if the edge a-b is shared by two triangles.
  bool is_interior(std::uint32_t a, std::uint32_t b) const {
    for (std::size_t t = 0; t < tris_.size(); ++t)
      for (int k = 0; k < 3; ++k)
        if (tris_[t][k] == a && tris_[t][(k + 1) % 3] == b) return nbr_[t][k] >= 0;
    return false;
  }

  void make_delaunay() {
    std::vector<std::pair<int, int>> stack;
    for (std::size_t i = 0; i < tris_.size(); ++i)
      for (int k = 0; k < 3; ++k) stack.emplace_back(static_cast<int>(i), k);
    legalize(stack);
  }

  /// Inserts `p` if it lies strictly inside a triangle (appending it to the points).
  bool insert(const glm::dvec2& p) {
    const int t = locate(p);
    if (t < 0) return false;
    const auto id = static_cast<std::uint32_t>(pts_.size());
    pts_.push_back(p);
    const LocalTri old = tris_[t];
    const auto n = nbr_[t];
    const int t1 = static_cast<int>(tris_.size()), t2 = t1 + 1;
    tris_[t] = {old[0], old[1], id};
    tris_.push_back({old[1], old[2], id});
    tris_.push_back({old[2], old[0], id});
    nbr_[t] = {n[0], t1, t2};
    nbr_.push_back({n[1], t2, t});
    nbr_.push_back({n[2], t, t1});
    relink(n[1], t, t1);
    relink(n[2], t, t2);
    std::vector<std::pair<int, int>> stack = {{t, 0}, {t1, 0}, {t2, 0}};
    legalize(stack);
    last_ = static_cast<std::size_t>(t);
    return true;
  }

 private:
  void relink(int n, int from, int to) {
    if (n < 0) return;
    for (int k = 0; k < 3; ++k)
      if (nbr_[n][k] == from) nbr_[n][k] = to;
  }

  double orient_rel(std::uint32_t a, std::uint32_t b, const glm::dvec2& p) const {
    const glm::dvec2 e = pts_[b] - pts_[a], f = p - pts_[a];
    const double scale = std::max(glm::dot(e, e), glm::dot(f, f));
    const double o = e.x * f.y - e.y * f.x;
    return std::abs(o) <= 1e-12 * scale ? 0.0 : o;
  }

  int locate(const glm::dvec2& p) const {
    int t = last_ < tris_.size() ? static_cast<int>(last_) : 0;
    for (std::size_t steps = 0; steps < tris_.size() + 3; ++steps) {
      int next = -2;
      for (int k = 0; k < 3 && next == -2; ++k)
        if (orient_rel(tris_[t][k], tris_[t][(k + 1) % 3], p) < 0.0) next = nbr_[t][k];
      if (next == -2) break;  // inside (or on an edge)
      if (next < 0) return scan(p);
      t = next;
    }
    for (int k = 0; k < 3; ++k)
      if (orient_rel(tris_[t][k], tris_[t][(k + 1) % 3], p) <= 0.0) return scan(p);
    return t;
  }

  int scan(const glm::dvec2& p) const {
    for (std::size_t t = 0; t < tris_.size(); ++t) {
      bool in = true;
      for (int k = 0; k < 3 && in; ++k) in = orient_rel(tris_[t][k], tris_[t][(k + 1) % 3], p) > 0.0;
      if (in) return static_cast<int>(t);
    }
    return -1;
  }

  void legalize(std::vector<std::pair<int, int>>& stack) {
    std::size_t guard = 64 * (tris_.size() + 16) * (tris_.size() + 16);
    while (!stack.empty() && guard-- > 0) {
      const auto [t, k] = stack.back();
      stack.pop_back();
      const int u = nbr_[t][k];
      if (u < 0) continue;
      const std::uint32_t a = tris_[t][k], b = tris_[t][(k + 1) % 3], c = tris_[t][(k + 2) % 3];
      int j = -1;
      for (int m = 0; m < 3; ++m)
        if (tris_[u][m] == b && tris_[u][(m + 1) % 3] == a) j = m;
      if (j < 0) continue;
      const std::uint32_t d = tris_[u][(j + 2) % 3];
      if (d == c) continue;
      const glm::dvec2 &pa = pts_[a], &pb = pts_[b], &pc = pts_[c], &pd = pts_[d];
      double scale = 0.0;
      for (const auto* q : {&pa, &pb, &pc}) scale = std::max(scale, glm::dot(*q - pd, *q - pd));
      if (incircle(pa, pb, pc, pd) <= 1e-10 * scale * scale) continue;
      if (orient(pc, pa, pd) <= 0.0 || orient(pd, pb, pc) <= 0.0) continue;
      const int n_bc = nbr_[t][(k + 1) % 3], n_ca = nbr_[t][(k + 2) % 3];
      const int n_ad = nbr_[u][(j + 1) % 3], n_db = nbr_[u][(j + 2) % 3];
      tris_[t] = {c, a, d};
      nbr_[t] = {n_ca, n_ad, u};
      tris_[u] = {d, b, c};
      nbr_[u] = {n_db, n_bc, t};
      relink(n_ad, u, t);
      relink(n_bc, t, u);
      stack.emplace_back(t, 0);
      stack.emplace_back(t, 1);
      stack.emplace_back(u, 0);
      stack.emplace_back(u, 1);
    }
  }

  std::vector<glm::dvec2>& pts_;
  std::vector<LocalTri> tris_;
  std::vector<std::array<int, 3>> nbr_;
  std::size_t last_ = 0;
};


}  // namespace deepcut::drill
