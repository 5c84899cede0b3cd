// SPDX-License-Identifier: MIT
#include "geometry/polygon_triangulation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <tuple>

namespace deepcut::geometry {
namespace {

double cross(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

bool point_in_loop(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& loop, const glm::dvec2& p) {
  bool inside = false;
  for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
    const auto& a = pts[loop[i]];
    const auto& b = pts[loop[j]];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
  }
  return inside;
}

bool segments_cross(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, const glm::dvec2& d) {
  const double d1 = cross(a, b, c), d2 = cross(a, b, d), d3 = cross(c, d, a), d4 = cross(c, d, b);
  return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

// Joins `hole` into `outer` with a bridge from the hole's rightmost point to a visible outer point.
void bridge_hole(const std::vector<glm::dvec2>& pts, std::vector<std::uint32_t>& outer, const std::vector<std::uint32_t>& hole) {
  std::size_t hi = 0;
  for (std::size_t i = 1; i < hole.size(); ++i)
    if (pts[hole[i]].x > pts[hole[hi]].x) hi = i;
  const glm::dvec2 h = pts[hole[hi]];
  // Candidate outer vertices sorted by distance; take the nearest whose bridge crosses no edge.
  std::vector<std::size_t> order(outer.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return glm::length(pts[outer[a]] - h) < glm::length(pts[outer[b]] - h);
  });
  std::size_t best = order.front();
  for (std::size_t candidate : order) {
    const glm::dvec2 o = pts[outer[candidate]];
    bool blocked = false;
    for (std::size_t i = 0; i < outer.size() && !blocked; ++i) {
      const std::uint32_t a = outer[i], b = outer[(i + 1) % outer.size()];
      if (a == outer[candidate] || b == outer[candidate]) continue;
      blocked = segments_cross(h, o, pts[a], pts[b]);
    }
    for (std::size_t i = 0; i < hole.size() && !blocked; ++i) {
      const std::uint32_t a = hole[i], b = hole[(i + 1) % hole.size()];
      if (a == hole[hi] || b == hole[hi]) continue;
      blocked = segments_cross(h, o, pts[a], pts[b]);
    }
    if (!blocked) {
      best = candidate;
      break;
    }
  }
  std::vector<std::uint32_t> merged;
  merged.reserve(outer.size() + hole.size() + 2);
  for (std::size_t i = 0; i <= best; ++i) merged.push_back(outer[i]);
  for (std::size_t k = 0; k <= hole.size(); ++k) merged.push_back(hole[(hi + k) % hole.size()]);
  merged.push_back(outer[best]);
  for (std::size_t i = best + 1; i < outer.size(); ++i) merged.push_back(outer[i]);
  outer.swap(merged);
}

// Ear clipping of one (possibly bridged, so weakly simple) counter-clockwise polygon. Ears are
// taken best-shaped first from a priority queue; only reflex vertices can lie inside an ear, so
// only they are tested, and clipping a vertex re-evaluates just its two neighbours.
void clip_ears(const std::vector<glm::dvec2>& pts, std::vector<std::uint32_t> poly,
               std::vector<std::array<std::uint32_t, 3>>& out) {
  poly.erase(std::unique(poly.begin(), poly.end()), poly.end());
  while (poly.size() > 1 && poly.front() == poly.back()) poly.pop_back();
  const std::size_t n = poly.size();
  if (n < 3) return;
  std::vector<std::size_t> prev(n), next(n);
  for (std::size_t i = 0; i < n; ++i) {
    prev[i] = (i + n - 1) % n;
    next[i] = (i + 1) % n;
  }
  std::vector<char> alive(n, 1), reflex(n, 0);
  std::vector<std::uint32_t> version(n, 0);
  std::vector<std::size_t> reflex_list;
  auto corner = [&](std::size_t i) { return cross(pts[poly[prev[i]]], pts[poly[i]], pts[poly[next[i]]]); };
  auto update_reflex = [&](std::size_t i) {
    const bool r = corner(i) <= 0.0;
    if (r && !reflex[i]) reflex_list.push_back(i);
    reflex[i] = r;
  };
  auto is_ear = [&](std::size_t i) {
    if (reflex[i]) return false;
    const std::uint32_t ia = poly[prev[i]], ib = poly[i], ic = poly[next[i]];
    const auto &a = pts[ia], &b = pts[ib], &c = pts[ic];
    for (std::size_t q : reflex_list) {
      if (!alive[q] || !reflex[q]) continue;
      const std::uint32_t iq = poly[q];
      if (iq == ia || iq == ib || iq == ic) continue;  // the same point (bridges repeat points)
      const auto& p = pts[iq];
      if (cross(a, b, p) >= 0 && cross(b, c, p) >= 0 && cross(c, a, p) >= 0) return false;
    }
    return true;
  };
  auto quality = [&](std::size_t i) {
    const auto &a = pts[poly[prev[i]]], &b = pts[poly[i]], &c = pts[poly[next[i]]];
    const double longest = std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
    return corner(i) / std::max(longest, 1e-300);
  };
  struct Entry {
    double quality;
    std::size_t i;
    std::uint32_t version;
    bool operator<(const Entry& o) const { return quality < o.quality; }
  };
  std::priority_queue<Entry> ears;
  for (std::size_t i = 0; i < n; ++i) update_reflex(i);
  for (std::size_t i = 0; i < n; ++i)
    if (is_ear(i)) ears.push({quality(i), i, version[i]});
  std::size_t remaining = n;
  std::size_t start = 0;  // some alive vertex
  while (remaining > 3) {
    std::size_t i = n;
    while (!ears.empty()) {
      const Entry e = ears.top();
      ears.pop();
      if (alive[e.i] && e.version == version[e.i]) {
        i = e.i;
        break;
      }
    }
    bool emit = true;
    if (i == n) {
      // No ear (numerically degenerate input): clip the most convex corner so the loop ends.
      double best = -std::numeric_limits<double>::max();
      std::size_t j = start;
      for (std::size_t k = 0; k < remaining; ++k, j = next[j])
        if (corner(j) > best) {
          best = corner(j);
          i = j;
        }
      emit = best > 0.0;
    }
    const std::size_t a = prev[i], c = next[i];
    if (emit) out.push_back({poly[a], poly[i], poly[c]});
    alive[i] = 0;
    next[a] = c;
    prev[c] = a;
    start = a;
    --remaining;
    for (std::size_t j : {a, c}) {
      ++version[j];
      update_reflex(j);
      if (is_ear(j)) ears.push({quality(j), j, version[j]});
    }
  }
  const std::size_t a = start, b = next[a], c = next[b];
  if (cross(pts[poly[a]], pts[poly[b]], pts[poly[c]]) > 0.0) out.push_back({poly[a], poly[b], poly[c]});
}

}  // namespace

double signed_area2(const std::vector<glm::dvec2>& points, const std::vector<std::uint32_t>& loop) {
  double a = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const auto& p = points[loop[i]];
    const auto& q = points[loop[(i + 1) % loop.size()]];
    a += p.x * q.y - q.x * p.y;
  }
  return a;
}

std::vector<std::array<std::uint32_t, 3>> triangulate_loops(const std::vector<glm::dvec2>& points,
                                                             const std::vector<std::vector<std::uint32_t>>& loops,
                                                             int outer_sign) {
  // Work counter-clockwise: mirror when the outer loops are clockwise, flip the output back.
  std::vector<glm::dvec2> pts = points;
  if (outer_sign < 0)
    for (auto& p : pts) p.x = -p.x;
  std::vector<std::size_t> outers, holes;
  std::vector<double> area(loops.size());
  for (std::size_t i = 0; i < loops.size(); ++i) {
    if (loops[i].size() < 3) continue;
    area[i] = signed_area2(pts, loops[i]);
    if (area[i] > 0) outers.push_back(i);
    else if (area[i] < 0) holes.push_back(i);
  }
  std::vector<std::vector<std::size_t>> holes_of(loops.size());
  for (std::size_t h : holes) {
    std::size_t owner = loops.size();
    for (std::size_t o : outers)
      if (point_in_loop(pts, loops[o], pts[loops[h][0]]) && (owner == loops.size() || area[o] < area[owner])) owner = o;
    if (owner != loops.size()) holes_of[owner].push_back(h);
  }
  std::vector<std::array<std::uint32_t, 3>> out;
  for (std::size_t o : outers) {
    std::vector<std::uint32_t> poly = loops[o];
    // Bridge holes from right to left so earlier bridges do not block later ones.
    auto& hs = holes_of[o];
    std::sort(hs.begin(), hs.end(), [&](std::size_t a, std::size_t b) {
      auto maxx = [&](std::size_t l) {
        double m = -std::numeric_limits<double>::max();
        for (auto i : loops[l]) m = std::max(m, pts[i].x);
        return m;
      };
      return maxx(a) > maxx(b);
    });
    for (std::size_t h : hs) bridge_hole(pts, poly, loops[h]);
    clip_ears(pts, poly, out);
  }
  // Mirroring reversed orientation once, so `out` already has the outer loops' orientation.
  return out;
}

// Ear clipping of one counter-clockwise, weakly simple polygon (indices into `pts`; a bridged
// hole repeats two points). An ear must have positive area and no other polygon point in its
// closed triangle, so points on a diagonal (collinear rim and edge points) never make T-junctions.
// Best-shaped ears first.
void clip_polygon(const std::vector<glm::dvec2>& pts, std::vector<std::uint32_t> poly,
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
std::vector<std::uint32_t> bridge(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& outer,
                                  const std::vector<std::uint32_t>& hole,
                                  const std::vector<std::vector<std::uint32_t>>& others) {
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
std::vector<LocalTri> triangulate(const std::vector<glm::dvec2>& pts,
                                  const std::vector<std::vector<std::uint32_t>>& loops) {
  std::vector<LocalTri> out;
  clip_polygon(pts, loops.size() > 1 ? bridge(pts, loops[0], loops[1]) : loops[0], out);
  return out;
}

}  // namespace deepcut::geometry
